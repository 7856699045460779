// Global injectivity with a free lattice boundary.
//
// det J > 0 in every cell (Gain & Dodgson 2001, Theorem 1) makes the deformation locally injective. With the
// boundary control points fixed the clamped volume maps its box onto itself, and local injectivity is then
// global. With a free boundary it is not: a slab bent round until its ends meet has det J > 0 everywhere
// and still overlaps itself. A locally injective map of the box is globally injective when the image of the
// box's boundary does not intersect itself (a closed surface bounding the image), so the engine also checks
// the deformed boundary surface, tessellated, for self-intersection whenever an operation moves a boundary
// control point.
#pragma once

#include <vector>

#include "core/volume/lattice.h"
#include "core/injectivity/self_intersection.h"

namespace sculpt::core {

// The deformed outer surface of the lattice, sampled `samplesPerSpan` times per knot span along each axis and
// triangulated as one closed, welded surface (shared vertices along the box's edges and corners), outward
// facing at rest. samplesPerSpan >= 1. The same lattice shape always gives the same vertex and triangle ids.
// Tensor-product kinds (the box lattice and LatticeNet: their outer surface is the parameter box's faces that
// are neither seams nor collapsed); asserted.
void latticeBoundarySurface(const Lattice& lattice, int samplesPerSpan, Positions& positions, Triangles& triangles);

// The intersecting triangle pairs of that surface (empty: the boundary does not overlap itself at this
// sampling). Exact predicates on the sampled surface: the curved surface between samples is not tested.
std::vector<TrianglePairHit> boundarySelfIntersections(const Lattice& lattice, int samplesPerSpan = 4);

}  // namespace sculpt::core
