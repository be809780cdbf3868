#version 450
// placeholder: being written
void main() {}
