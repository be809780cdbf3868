#version 450
// placeholder: being written
layout(local_size_x = 1) in;
void main() {}
