// The trace list (hybrid/compact_pass.h) through its device address, FrameData::tracePoints, so
// that it may hold more points than one storage binding spans (2.8 M on lavapipe's 128 MiB).
// Included after `frame` is declared; includers enable GL_EXT_buffer_reference and
// GL_EXT_buffer_reference_uvec2.
#include "shared/shading_point.h"
layout(buffer_reference, std430, buffer_reference_align = 16) buffer ShadingPoints { ShadingPoint v[]; };
#define pointList ShadingPoints(frame.tracePoints).v
