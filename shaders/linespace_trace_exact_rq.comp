#version 460
// Shadow rays of the line-space tracer in exact mode (leaf triangles tested); moving meshes on the
// driver's acceleration structures (linespace_trace.glsl), where the device has ray queries.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#define LS_EXACT
#define LS_MOVING_RAY_QUERY
#include "linespace_trace.glsl"
