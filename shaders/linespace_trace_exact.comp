#version 450
// Shadow rays of the line-space tracer in exact mode (leaf triangles tested); moving meshes on
// their own BVH (linespace_trace.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#define LS_EXACT
#include "linespace_trace.glsl"
