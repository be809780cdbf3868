// Lets one header be compiled as GLSL and as C++ (GLM mirrors GLSL's types and functions).
// Shared code uses no swizzles and no GLSL-only built-ins beyond what GLM provides.
#ifndef PENUMBRA_GLSL_CPP_H
#define PENUMBRA_GLSL_CPP_H
#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
#define PN_BEGIN namespace penumbra::shared { using namespace glm; using uint = std::uint32_t;
#define PN_END }
#define PN_FN inline
#else
#define PN_BEGIN
#define PN_END
#define PN_FN
#endif
#endif
