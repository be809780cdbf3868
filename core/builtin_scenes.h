// Procedural scenes selectable as "builtin:NAME" or "builtin:courtyard[-moving]:LEVEL" (LEVEL = tessellation).
// Each comes with its default camera and light.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"

namespace penumbra {

// All scenes: Y up, per-vertex unit normals (flat on boxes and planes), triangles counter-clockwise
// seen from the side the normals face, one base colour per object, one light, a camera, and
// scene.name "builtin:NAME". cleanScene drops none of their triangles. Only the courtyards take a
// LEVEL (and the street its lamp count); any other level, or an unknown name, is an InputError
// listing the names and the syntax.
//
// courtyard[:LEVEL] (LEVEL 1..512, default 8): 24 x 24 ground grid at y = 0 (8*LEVEL cells a side),
//            three boxes, five columns (r 0.35, h 4, 8*LEVEL segments) at z = -6, a UV sphere
//            (r 1.2, 12*min(LEVEL,128) x 6*min(LEVEL,128)), an upright torus (12*LEVEL x 6*LEVEL),
//            a fence of 20 bars 0.24 wide at x = 7.5 and six wires 0.05 thick at y = 3 strung along
//            x between two posts at z = 6. Radius 17.09 (bars 0.014, wires 0.0029 of it).
//            Triangles: 272*L^2 + 144*S^2 + 160*L - 24*S + 408 with S = min(L, 128):
//              LEVEL 1: 960     8: 28,120     32: 430,744     64: 1,713,048 (>= 1M)
//              128: 6,833,560   512: 73,741,720 (gigabytes of memory)
//            Light: Disk, size 0, at (-16, 22, -1) facing the bounds centre (0, 2, 0).
//            Camera: eye (7, 17, 22), target (0.8, 0, 0.6), fovy 45; all objects and shadows in view.
// courtyard-moving[:LEVEL]: the courtyard plus a dynamic "drone" (a 1 x 0.24 x 1 body and two
//            crossed 3.2 x 0.04 x 0.06 rotor bars, 36 triangles) animated by rigid keys (core/animation.h):
//            a circle of radius 3.5 about (0.5, 3.6, 0.5), spinning, looped every 8 s. Posed at t = 0.
// wires:     40 x 40 ground (2 triangles) at y = 0 under 10 + 10 wires (boxes 0.012 thick, 3 long,
//            0.3 apart, turned 7 degrees about y) at y = 1.0 and 1.02. Radius 28.29, so a 2048^2
//            shadow-map texel over the bounding sphere is 0.0276 (wires < half a texel).
//            Light: Directional, travel direction normalize(0.15, -1, 0.1).
//            Camera: target (0.1, 0, 0.1), eye 3.4 away looking down 50 degrees from -z, fovy 25:
//            at 256 x 256 a wire's shadow spans >= 1.5 pixels.
// square:    the known answer. Ground [-5,5] x [-5,5] at y = 0 and occluder [-1,1] x [-1,1] at
//            y = 1, two triangles each, normals +y. Light: Directional, travel direction
//            d = normalize(0.3, -1, 0.2). A ground point p is shadowed iff p - t*d (t > 0) meets
//            the occluder, i.e. the shadow is [-0.7, 1.3] x [-0.8, 1.2] at y = 0.
//            Camera: eye (0, 9, 9), target (0.3, 0, 0.2), fovy 45.
// checker:   the square with its occluder cut out (Cutout, alpha-tested): texture coordinates
//            u = (x + 1) / 2, v = (z + 1) / 2 over a kCheckerCells^2 (8^2) texture whose texel (i, j) has
//            alpha 1 where i + j is even, else 0, cutoff 0.5. A ground point is shadowed iff its
//            occluder point q = p - t*d lies in a solid cell: floor(u * 8) + floor(v * 8) even.
// room:      closed room x, z in [-5, 5], y in [0, 4] (walls, floor, ceiling facing inward), a
//            crate, a floor-to-ceiling pillar and a ball hanging on a cord above the light.
//            Light: Point at (1.2, 2, -1); shadows land on the floor, ceiling and walls.
//            Camera: eye (4.4, 3.2, 4.4) in a corner, target (-2, 1.2, -2), fovy 60.
// street[:LAMPS] (LAMPS 1..256, default 16): many lights. A road grid at y = 0, 14 wide, from
//            x = -3 as far as the lamps need; LAMPS lamp posts (r 0.06 cylinders 3.9 high with an
//            arm) alternating between the pavements at z = +-4.5, from x = 0 every 3 along x, each
//            with a bench seat and 12 railing bars 0.03 wide at z = +-6.2. Lights: one Point per lamp
//            3.6 above the road, inverse-square with intensity 3.6^2 (irradiance 1 below it) and
//            range 7, so that neighbours' ranges barely overlap. Camera: the same for every LAMPS,
//            eye (-4, 6, 0) looking along the street at (12, 0, 0), fovy 60.
// foliage, level, knot: stress scenes (a tree of small leaves, a brush-built level with sub-texel
//            cracks, a self-shadowing knot), documented in core/stress_scenes.h.
Scene makeBuiltinScene(const std::string& nameAndLevel);
inline constexpr std::uint32_t kCheckerCells = 8;  // builtin:checker's texels a side
// The triangles makeBuiltinScene would build for a courtyard spec, counted without building it
// (its levels reach tens of millions); nullopt for the other scenes, which are small.
std::optional<std::uint64_t> builtinTriangleCount(const std::string& nameAndLevel);
std::vector<std::string> builtinSceneNames();

}  // namespace penumbra
