// Built-in stress scenes: content that looks like real scenes and defeats shadow-map
// classification. makeBuiltinScene ("builtin:foliage", "builtin:level", "builtin:knot") builds them;
// they follow the conventions of core/builtin_scenes.h (Y up, unit per-vertex normals, CCW seen from
// the normal side, one base colour per mesh, cleanScene keeps every triangle). All are deterministic:
// random placement uses std::mt19937 with a fixed seed and its own mapping to floats. Each light is a
// Disk of size 0 (widen it with --light-size) aimed at the bounds centre.
//
// foliage:   a small tree without ground: trunk (cylinder r 0.11, y 0 .. 2, 16 segments), 7 branches
//            (cylinders r 0.035, 8 segments: six spiralling up the trunk, a leader on top) and 7,000
//            single-sided leaf quads 0.06 .. 0.10 long (0.027 .. 0.045 of the radius 2.23), turned at
//            random and packed within 0.32 of the outer 70 % of the branches, so leaves shadow leaves
//            (most leaf centres are in shadow). Nothing lies below the trunk base y = 0.
//            Triangles: 64 + 7*32 + 7,000*2 = 14,288.
//            Light at (3, 6.5, 2). Camera: eye (1, 2.5, 4), target (0.15, 2.15, -0.05), fovy 45.
// level:     a brush-built level piece, 17 boxes and a decal (206 triangles), on a 12 x 20 floor slab
//            (top y = 0, x in [-6, 6], z in [-10, 10]). A slatted wall at z = 0 (five boards 0.05
//            thick, 2.5 high, between posts under a lintel) has four vertical cracks 0.003 .. 0.005
//            wide, 0.22 .. 0.37 of the 2048^2 shadow-map texel there (0.0134); the light passes
//            through them into a room behind, drawing light lines on its floor and up its back wall
//            (x in [-4, 4], z = 6 .. 6.2). T-junctions: the boards and lintel end on the posts' faces,
//            a partition (x = 2 .. 2.2) runs from a board's back face to the back wall, three pillars
//            end under the middle of a beam. Coplanar: a patch slab whose top overlaps the floor top
//            at y = 0, and a decal quad on the floor at y = 0. A thin wall 0.004 thick (0.37 texel)
//            stands turned 35 degrees in front of the slats. The light grazes the long floor at 5 .. 10
//            degrees over z in [-6, 10] (12 at z = -10).
//            Light at (0, 3, -24), in line with the cracks. Camera: eye (-3.2, 4.2, -1.2) over the
//            slatted wall, target (0.6, 0.6, 5.5), fovy 55.
// knot:      a (2, 3) torus knot (trefoil) tube without ground: centre line
//            ((1.6 + 0.7 cos 3t) cos 2t, 0.7 sin 3t, (1.6 + 0.7 cos 3t) sin 2t), tube radius 0.4,
//            512 x 32 quads with smooth normals, closed (every edge shared by two triangles). Strands
//            pass over each other and the light comes from the side, so the knot shadows itself.
//            Triangles: 512*32*2 = 32,768.
//            Light at (4.5, 3.5, 2). Camera: eye (0.5, 3.2, 6.4), target (0, 0, 0), fovy 45.
#pragma once
#include "core/scene.h"

namespace penumbra {

Scene foliageScene();
Scene levelScene();
Scene knotScene();

}  // namespace penumbra
