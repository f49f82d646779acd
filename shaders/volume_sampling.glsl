// Sampling the CT volume: an R16_UNORM 3D image holding HU + 32768 (every int16 value kept),
// read through a linear sampler: hardware trilinear filtering (the fastest exact path), or a
// cubic B-spline built from eight trilinear fetches (smoother, for still frames).
#ifndef VOLUME_SAMPLING_GLSL
#define VOLUME_SAMPLING_GLSL

float huFromUnorm(float v) { return v * 65535.0 - 32768.0; }

vec3 texFromMm(vec3 pMm) { return pMm * u.texFromMmScale.xyz + u.texFromMmOffset.xyz; }

float fetchTrilinear(vec3 tc) {
    if (kCountFetches) ++gFetchCount;
    return textureLod(volumeTexture, tc, 0.0).r;
}

// Tricubic B-spline from 8 trilinear fetches (Sigg and Hadwiger, GPU Gems 2, ch. 20): per
// axis the four B-spline weights fold into two linear fetches at shifted positions.
float fetchTricubic(vec3 tc) {
    vec3 dims = u.volumeDims.xyz;
    vec3 coord = tc * dims - 0.5;  // voxel centres at integers
    vec3 index = floor(coord);
    vec3 f = coord - index;
    vec3 oneMinusF = 1.0 - f;
    vec3 w0 = oneMinusF * oneMinusF * oneMinusF / 6.0;
    vec3 w1 = 2.0 / 3.0 - 0.5 * f * f * (2.0 - f);
    vec3 w2 = 2.0 / 3.0 - 0.5 * oneMinusF * oneMinusF * (2.0 - oneMinusF);
    vec3 w3 = f * f * f / 6.0;
    vec3 g0 = w0 + w1;
    vec3 g1 = w2 + w3;
    // Fetch positions in voxel units, then back to texture coordinates.
    vec3 p0 = (index - 1.0 + w1 / g0 + 0.5) / dims;
    vec3 p1 = (index + 1.0 + w3 / g1 + 0.5) / dims;
    float v000 = fetchTrilinear(vec3(p0.x, p0.y, p0.z));
    float v100 = fetchTrilinear(vec3(p1.x, p0.y, p0.z));
    float v010 = fetchTrilinear(vec3(p0.x, p1.y, p0.z));
    float v110 = fetchTrilinear(vec3(p1.x, p1.y, p0.z));
    float v001 = fetchTrilinear(vec3(p0.x, p0.y, p1.z));
    float v101 = fetchTrilinear(vec3(p1.x, p0.y, p1.z));
    float v011 = fetchTrilinear(vec3(p0.x, p1.y, p1.z));
    float v111 = fetchTrilinear(vec3(p1.x, p1.y, p1.z));
    float z0 = g0.y * (g0.x * v000 + g1.x * v100) + g1.y * (g0.x * v010 + g1.x * v110);
    float z1 = g0.y * (g0.x * v001 + g1.x * v101) + g1.y * (g0.x * v011 + g1.x * v111);
    return g0.z * z0 + g1.z * z1;
}

float fetchFiltered(vec3 tc) {
    return kFilter == CVC_FILTER_TRICUBIC ? fetchTricubic(tc) : fetchTrilinear(tc);
}

float sampleHu(vec3 pMm) { return huFromUnorm(fetchFiltered(texFromMm(pMm))); }

// Central-difference gradient in HU per mm, one voxel to each side. For trilinear filtering,
// shifting by exactly one voxel keeps the weights, so this equals the voxels' own central
// differences blended trilinearly: continuous across voxel planes.
vec3 gradientHu(vec3 pMm) {
    vec3 tc = texFromMm(pMm);
    vec3 h = 1.0 / u.volumeDims.xyz;
    float dx = fetchFiltered(tc + vec3(h.x, 0, 0)) - fetchFiltered(tc - vec3(h.x, 0, 0));
    float dy = fetchFiltered(tc + vec3(0, h.y, 0)) - fetchFiltered(tc - vec3(0, h.y, 0));
    float dz = fetchFiltered(tc + vec3(0, 0, h.z)) - fetchFiltered(tc - vec3(0, 0, h.z));
    return vec3(dx, dy, dz) * 65535.0 * 0.5 * u.invSpacingMm.xyz;
}

bool isInsideBox(vec3 pMm) {
    return all(greaterThanEqual(pMm, u.boxMinMm.xyz)) && all(lessThanEqual(pMm, u.boxMaxMm.xyz));
}

#endif
