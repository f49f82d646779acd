// Empty-space skipping over 8^3 bricks: one byte per brick says whether any sample inside it
// (its one-voxel apron included, which trilinear filtering reads) can contribute; a ray
// crosses an empty brick in one step.
#ifndef EMPTY_SPACE_GLSL
#define EMPTY_SPACE_GLSL

// Brick b covers voxel coordinates [8b - 0.5, 8b + 7.5) on each axis (voxel centres at
// integers), i.e. the part of the box where a sample's nearest-voxel cell lies in b.
ivec3 brickOf(vec3 pMm) {
    return ivec3(floor((pMm * u.invSpacingMm.xyz + 0.5) * (1.0 / float(CVC_BRICK_SIZE))));
}

bool isBrickOccupied(ivec3 brick) {
    ivec3 last = textureSize(brickOccupancy, 0) - 1;
    if (any(lessThan(brick, ivec3(0))) || any(greaterThan(brick, last))) return false;
    return texelFetch(brickOccupancy, brick, 0).r != 0u;
}

// Ray parameter where origin + t * dir leaves brick `brick`.
float brickExitT(vec3 origin, vec3 invDir, ivec3 brick) {
    vec3 spacing = 1.0 / u.invSpacingMm.xyz;
    vec3 lo = (vec3(brick) * float(CVC_BRICK_SIZE) - 0.5) * spacing;
    vec3 hi = lo + float(CVC_BRICK_SIZE) * spacing;
    vec3 t0 = (lo - origin) * invDir;
    vec3 t1 = (hi - origin) * invDir;
    vec3 tFar = max(t0, t1);
    return min(min(tFar.x, tFar.y), tFar.z);
}

#endif
