// placeholder: being written (included by bvh_*.comp)
