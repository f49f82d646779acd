// Sampling the CT volume: an R16_UNORM 3D image holding HU + 32768 (every int16 value kept),
// read through a linear sampler: hardware trilinear filtering (the fastest exact path), or a
// cubic B-spline built from eight trilinear fetches (smoother, for still frames).
#ifndef VOLUME_SAMPLING_GLSL
#define VOLUME_SAMPLING_GLSL

float huFromUnorm(float v) { return v * 65535.0 - 32768.0; }

vec3 texFromMm(vec3 pMm) { return pMm * u.texFromMmScale + u.texFromMmOffset; }

float fetchTrilinear(vec3 tc) {
    if (kCountFetches) ++gFetchCount;
    return textureLod(volumeTexture, tc, 0.0).r;
}

// The cubic B-spline from trilinear fetches (Sigg and Hadwiger, GPU Gems 2, ch. 20): per axis
// the four (positive) weights of the texels index-1 .. index+2 fold into two linear fetches at
// shifted positions, so a value costs 8 fetches.
struct BSplineAxes {
    vec3 index;  // voxel index of the texel below the point, per axis
    vec3 f;      // fraction of the way to the next texel
};

BSplineAxes bsplineAxes(vec3 tc) {
    vec3 coord = tc * u.volumeDims - 0.5;  // voxel centres at integers
    BSplineAxes a;
    a.index = floor(coord);
    a.f = coord - a.index;
    return a;
}

// Weights (w0 + w1, w2 + w3) of the B-spline per axis and the two fetch positions (texture
// coordinates) that carry them.
void bsplineWeights(BSplineAxes a, out vec3 g0, out vec3 g1, out vec3 p0, out vec3 p1) {
    vec3 f = a.f;
    vec3 oneMinusF = 1.0 - f;
    vec3 w0 = oneMinusF * oneMinusF * oneMinusF / 6.0;
    vec3 w1 = 2.0 / 3.0 - 0.5 * f * f * (2.0 - f);
    vec3 w2 = 2.0 / 3.0 - 0.5 * oneMinusF * oneMinusF * (2.0 - oneMinusF);
    vec3 w3 = f * f * f / 6.0;
    g0 = w0 + w1;
    g1 = w2 + w3;
    p0 = (a.index - 1.0 + w1 / g0 + 0.5) / u.volumeDims;
    p1 = (a.index + 1.0 + w3 / g1 + 0.5) / u.volumeDims;
}

// The fetch of a B-spline's corner: the volume's value in x, or with isFromGradientVolume the
// gradient volume's three central differences in xyz.
vec3 fetchCorner(vec3 tc, bool isFromGradientVolume) {
    if (!isFromGradientVolume) return vec3(fetchTrilinear(tc), 0.0, 0.0);
    if (kCountFetches) ++gFetchCount;
    return textureLod(gradientVolume, tc, 0.0).xyz;
}

// Sum of the 8 fetches at the corners spanned by p0 and p1, weighted per axis by g0 and g1.
vec3 blendEightFetches(vec3 g0, vec3 g1, vec3 p0, vec3 p1, bool isFromGradientVolume) {
    vec3 v000 = fetchCorner(vec3(p0.x, p0.y, p0.z), isFromGradientVolume);
    vec3 v100 = fetchCorner(vec3(p1.x, p0.y, p0.z), isFromGradientVolume);
    vec3 v010 = fetchCorner(vec3(p0.x, p1.y, p0.z), isFromGradientVolume);
    vec3 v110 = fetchCorner(vec3(p1.x, p1.y, p0.z), isFromGradientVolume);
    vec3 v001 = fetchCorner(vec3(p0.x, p0.y, p1.z), isFromGradientVolume);
    vec3 v101 = fetchCorner(vec3(p1.x, p0.y, p1.z), isFromGradientVolume);
    vec3 v011 = fetchCorner(vec3(p0.x, p1.y, p1.z), isFromGradientVolume);
    vec3 v111 = fetchCorner(vec3(p1.x, p1.y, p1.z), isFromGradientVolume);
    vec3 z0 = g0.y * (g0.x * v000 + g1.x * v100) + g1.y * (g0.x * v010 + g1.x * v110);
    vec3 z1 = g0.y * (g0.x * v001 + g1.x * v101) + g1.y * (g0.x * v011 + g1.x * v111);
    return g0.z * z0 + g1.z * z1;
}

// The cubic B-spline of the volume (isFromGradientVolume false, in x) or of the gradient volume.
vec3 fetchBSpline(vec3 tc, bool isFromGradientVolume) {
    vec3 g0, g1, p0, p1;
    bsplineWeights(bsplineAxes(tc), g0, g1, p0, p1);
    return blendEightFetches(g0, g1, p0, p1, isFromGradientVolume);
}

float fetchTricubic(vec3 tc) { return fetchBSpline(tc, false).x; }

float fetchFiltered(vec3 tc) {
    return kFilter == CVC_FILTER_TRICUBIC ? fetchTricubic(tc) : fetchTrilinear(tc);
}

float sampleHu(vec3 pMm) { return huFromUnorm(fetchFiltered(texFromMm(pMm))); }

// Central-difference gradient in HU per mm, one voxel to each side, of the trilinear or the
// cubic B-spline interpolant. Trilinear (6 fetches): shifting by exactly one voxel keeps the
// weights, so this equals the voxels' own central differences blended trilinearly, continuous
// across voxel planes but with a kink at each, which coarse CT shows as one sharp shading band
// per voxel layer. B-spline (48 fetches): the same central differences blended by the cubic
// B-spline, twice continuously differentiable, so the normals turn smoothly; used only where a
// sample is shaded. (The B-spline's exact derivative, 24 fetches, was measured too: without
// the central difference's one-voxel averaging it shows the terraces sharper than trilinear;
// docs/benchmarks/normals.md.)
vec3 gradientCentralHu(vec3 pMm, bool isTricubic) {
    vec3 tc = texFromMm(pMm);
    vec3 h = 1.0 / u.volumeDims;
    float dx, dy, dz;
    if (isTricubic) {
        dx = fetchTricubic(tc + vec3(h.x, 0, 0)) - fetchTricubic(tc - vec3(h.x, 0, 0));
        dy = fetchTricubic(tc + vec3(0, h.y, 0)) - fetchTricubic(tc - vec3(0, h.y, 0));
        dz = fetchTricubic(tc + vec3(0, 0, h.z)) - fetchTricubic(tc - vec3(0, 0, h.z));
    } else {
        dx = fetchTrilinear(tc + vec3(h.x, 0, 0)) - fetchTrilinear(tc - vec3(h.x, 0, 0));
        dy = fetchTrilinear(tc + vec3(0, h.y, 0)) - fetchTrilinear(tc - vec3(0, h.y, 0));
        dz = fetchTrilinear(tc + vec3(0, 0, h.z)) - fetchTrilinear(tc - vec3(0, 0, h.z));
    }
    return vec3(dx, dy, dz) * 65535.0 * 0.5 * u.invSpacingMm;
}

// The same gradient read from the gradient volume (engine/render/gradient_volume.h), which holds
// each voxel's central differences: one fetch in place of 6 (trilinear), 8 in place of 48
// (B-spline), equal but for half-float rounding.
vec3 gradientFromVolumeHu(vec3 pMm, bool isTricubic) {
    vec3 tc = texFromMm(pMm);
    vec3 perVoxel = isTricubic ? fetchBSpline(tc, true) : fetchCorner(tc, true);
    return perVoxel * u.invSpacingMm;
}

bool isInsideBox(vec3 pMm) {
    return all(greaterThanEqual(pMm, u.boxMinMm)) && all(lessThanEqual(pMm, u.boxMaxMm));
}

#endif
