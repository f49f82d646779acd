// Empty-space skipping over a distance map: for each cell (cellVoxels^3 voxels) the Chebyshev
// distance, in cells, to the nearest cell that can contribute (its one-voxel apron included,
// which trilinear filtering reads). A ray in a cell at distance d > 1 can move (d - 1) cells
// in any direction without meeting anything, and does so in one step.
#ifndef EMPTY_SPACE_GLSL
#define EMPTY_SPACE_GLSL

float cellVoxels() { return u.skipCellVoxels; }

// Cell c covers voxel coordinates [s c - 0.5, s c + s - 0.5) on each axis (voxel centres at
// integers, s = cellVoxels), i.e. the samples whose trilinear footprint lies in its apron.
ivec3 cellOf(vec3 pMm) { return ivec3(floor((pMm * u.invSpacingMm + 0.5) / cellVoxels())); }

uint skipDistanceAt(ivec3 cell) {
    ivec3 last = textureSize(skipDistance, 0) - 1;
    return texelFetch(skipDistance, clamp(cell, ivec3(0), last), 0).r;
}

// Ray parameter where origin + t * dir leaves `cell`.
float cellExitT(vec3 origin, vec3 invDir, ivec3 cell) {
    vec3 spacing = 1.0 / u.invSpacingMm;
    vec3 lo = (vec3(cell) * cellVoxels() - 0.5) * spacing;
    vec3 hi = lo + cellVoxels() * spacing;
    vec3 t0 = (lo - origin) * invDir;
    vec3 t1 = (hi - origin) * invDir;
    vec3 tFar = max(t0, t1);
    return min(min(tFar.x, tFar.y), tFar.z);
}

#endif
