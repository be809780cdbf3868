#version 450
// placeholder: being written
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
void main() {}
