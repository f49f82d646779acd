// Sampling the CT volume: an R16_UNORM 3D image holding HU + 32768 (every int16 value kept),
// read through a linear sampler (hardware trilinear filtering, the fastest exact path).
#ifndef VOLUME_SAMPLING_GLSL
#define VOLUME_SAMPLING_GLSL

float huFromUnorm(float v) { return v * 65535.0 - 32768.0; }

vec3 texFromMm(vec3 pMm) { return pMm * u.texFromMmScale.xyz + u.texFromMmOffset.xyz; }

float sampleHu(vec3 pMm) { return huFromUnorm(textureLod(volumeTexture, texFromMm(pMm), 0.0).r); }

// Central-difference gradient in HU per mm, one voxel to each side. Shifting by exactly one
// voxel keeps the trilinear weights, so this equals the voxels' own central differences
// blended trilinearly: continuous across voxel planes, at 6 fetches per shaded hit.
vec3 gradientHu(vec3 pMm) {
    vec3 tc = texFromMm(pMm);
    vec3 h = u.voxelStepTex.xyz;
    float dx = textureLod(volumeTexture, tc + vec3(h.x, 0, 0), 0.0).r -
               textureLod(volumeTexture, tc - vec3(h.x, 0, 0), 0.0).r;
    float dy = textureLod(volumeTexture, tc + vec3(0, h.y, 0), 0.0).r -
               textureLod(volumeTexture, tc - vec3(0, h.y, 0), 0.0).r;
    float dz = textureLod(volumeTexture, tc + vec3(0, 0, h.z), 0.0).r -
               textureLod(volumeTexture, tc - vec3(0, 0, h.z), 0.0).r;
    return vec3(dx, dy, dz) * 65535.0 * 0.5 * u.invSpacingMm.xyz;
}

#endif
