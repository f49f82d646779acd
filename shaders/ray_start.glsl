// Skipping before marching: a pass over the image's tiles finds, for each tile of
// CVC_TILE_SIZE^2 pixels, a ray parameter before which all of the tile's rays cross only empty
// cells of the distance map. The march then starts there. One invocation per tile does the
// work once for 64 rays; in the march, lavapipe runs 8 rays as one vector, and the vector pays
// every lane's skips.
//
// The bound (cone marching, generalised to the tile's straight segments o_i + t d_i, whether
// they start at the eye or are bent chords): with a reference segment o + t d of the tile,
// alpha = max |o_i - o| and beta = max |d_i - d|, every point of every segment at a parameter
// t' in [t, t1] lies within alpha + t1 beta + (t1 - t) of o + t d. If the distance map leaves a
// ball of radius R empty around o + t d, all those points are empty as long as
// t1 <= (R - alpha + t) / (1 + beta), and t moves there. Pinhole rays share their origin
// (alpha = 0) and beta is the chord of the tile's angular radius: the usual cone.
#ifndef RAY_START_GLSL
#define RAY_START_GLSL

layout(constant_id = CVC_SPEC_RAY_START) const int kRayStart = CVC_RAY_START_NONE;
layout(std430, binding = CVC_BINDING_RAY_START) buffer RayStartTable { float rayStartTable[]; };

const int kMaxTileSkips = 256;  // cone-marching steps of one tile: ample, and a bound

// Radius of a ball around pMm that holds only empty cells: a cell at Chebyshev distance d has
// d - 1 empty cells beyond its own on every side. Less a hundredth of a cell, for the rounding
// by which the march's positions may differ from this pass's.
float emptyRadiusMm(vec3 pMm) {
    uint distanceCells = skipDistanceAt(cellOf(pMm));
    float cellMm = cellVoxels() * minSpacingMm();
    return (float(max(distanceCells, 1u)) - 1.01) * cellMm;
}

// The tile pass: writes tile's entry of the table. A tile none of whose rays meets the box
// gets 0 (its rays do not march anyway).
void writeTileStart(uvec2 tile) {
    uvec2 tiles = (u.imageSize + CVC_TILE_SIZE - 1) / CVC_TILE_SIZE;
    if (tile.x >= tiles.x || tile.y >= tiles.y) return;
    uvec2 first = tile * CVC_TILE_SIZE;
    uvec2 last = min(first + CVC_TILE_SIZE, u.imageSize) - 1u;
    uvec2 centre = (first + last) / 2u;
    Segment reference = segmentForPixel(centre);
    float alpha = 0.0;
    float beta = 0.0;
    float tFrom = 3.0e38;
    float tTo = -3.0e38;
    for (uint y = first.y; y <= last.y; ++y) {
        for (uint x = first.x; x <= last.x; ++x) {
            Segment s = uvec2(x, y) == centre ? reference : segmentForPixel(uvec2(x, y));
            if (s.tStart >= s.tEnd) continue;
            alpha = max(alpha, length(s.origin - reference.origin));
            beta = max(beta, length(s.dir - reference.dir));
            tFrom = min(tFrom, s.tStart);
            tTo = max(tTo, s.tEnd);
        }
    }
    float t = tFrom < tTo ? tFrom : 0.0;
    for (int i = 0; i < kMaxTileSkips && t < tTo; ++i) {
        float next = (emptyRadiusMm(reference.origin + t * reference.dir) - alpha + t) / (1.0 + beta);
        if (next < t + u.stepMm) break;  // less than a step gained: the march takes it from here
        t = next;
    }
    rayStartTable[tileIndexOf(tile)] = t;
}

// Where the march along s may start: its tile's entry when that lies beyond s.tStart. With a
// fixed step the start stays on the grid of parameters the ray would visit from s.tStart, so
// the samples, and the image, are those of a march from s.tStart.
float rayStartOf(Segment s, uvec2 pixel) {
    if (kRayStart != CVC_RAY_START_READ) return s.tStart;
    float tileStart = rayStartTable[tileIndexOf(pixel / CVC_TILE_SIZE)];
    if (!(tileStart > s.tStart)) return s.tStart;
    if (kAdaptive) return tileStart;
    return s.tStart + floor((tileStart - s.tStart) / u.stepMm) * u.stepMm;
}

#endif
