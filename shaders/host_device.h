/// @brief Structures, binding numbers and specialization constants shared by the C++ host code
/// and the GLSL shaders.
///
/// Included from C++ (with GLM types) and from GLSL (with its built-in types), so both sides
/// agree on every offset. Only 16-byte members are used: std140 and C++ then lay them out
/// identically (checked by static_asserts in engine/render/raycaster.cpp).
#ifndef CVC_HOST_DEVICE_H
#define CVC_HOST_DEVICE_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace shaders {
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
#endif

// Bindings of the ray caster (shaders/raycast.comp).
#define CVC_BINDING_UNIFORMS 0
#define CVC_BINDING_VOLUME 1
#define CVC_BINDING_COLOR_IMAGE 2
#define CVC_BINDING_HIT_IMAGE 3
#define CVC_BINDING_SKIP_DISTANCE 4  // the empty-space distance map
#define CVC_BINDING_TRANSFER_FUNCTION 5
#define CVC_BINDING_CUBE_MAP 6

// Specialization constants: choices fixed per pipeline, so a variant carries no code (and no
// fetches) for features it does not use.
#define CVC_SPEC_MODE 0        // CVC_MODE_*
#define CVC_SPEC_FILTER 1      // CVC_FILTER_*
#define CVC_SPEC_WARP 2        // CVC_WARP_*
#define CVC_SPEC_SKIPPING 3    // 1: empty-space skipping over bricks
#define CVC_SPEC_ADAPTIVE 4    // 1: adaptive step size
#define CVC_SPEC_COUNT_FETCHES 5  // 1: hit image w = texture fetches the ray made (benchmarks)
#define CVC_SPEC_GRADIENT 6    // CVC_GRADIENT_*: how shading normals are computed

#define CVC_MODE_ISO 0
#define CVC_MODE_COMPOSITE 1
#define CVC_FILTER_TRILINEAR 0
#define CVC_FILTER_TRICUBIC 1
#define CVC_WARP_NONE 0
#define CVC_WARP_CHORD 1   // map the near and far ends of the ray, march the chord (paper Eq. 7)
#define CVC_WARP_EXACT 2   // map every sample (the reference for stereo eyes)
#define CVC_GRADIENT_CENTRAL 0  // central differences of the filtered volume (6 trilinear fetches)
#define CVC_GRADIENT_BSPLINE 1  // central differences of the cubic B-spline interpolant (48 fetches, smooth)

// Bits of RaycastUniforms::frame.w
#define CVC_FLAG_WRITE_HITS 1u
#define CVC_FLAG_JITTER 2u
#define CVC_FLAG_WRITE_NORMALS 4u  // the hit image holds the shading normal (xyz) instead of the position

// Work-group size of the image-space shaders (pixels per group along x and y).
#define CVC_TILE_SIZE 8

/// Everything one ray-casting dispatch needs. Positions and lengths are in volume millimetres
/// (voxel (i, j, k) centred at (i, j, k) * spacing, see volumes/volume.h).
struct RaycastUniforms {
    // Rays: pixel (x, y) looks from the eye through wallOrigin + (x+.5)/w * wallU + (y+.5)/h * wallV.
    vec4 eyeMm;            // xyz: eye; w: near-plane distance from the eye along wallNormal
    vec4 wallOriginMm;     // xyz: corner of the image at pixel (0, 0)'s outer corner (top left)
    vec4 wallUMm;          // xyz: the image's full width, left to right
    vec4 wallVMm;          // xyz: the image's full height, top to bottom
    vec4 wallNormal;       // xyz: unit normal of the image plane, pointing away from the eye
    // Warp W(q) = c + |q - c| R F(R^T dir(q - c)) (paper Eq. 7), in volume millimetres.
    vec4 mapCentreMm;      // xyz: c, the map centre (the CAVE's centre) in the volume
    vec4 caveToVolume0;    // xyz: R's columns, CAVE x, y, z axes as unit volume vectors
    vec4 caveToVolume1;
    vec4 caveToVolume2;
    // Volume
    vec4 boxMinMm;         // xyz: lower corner of the volume's box (outer faces of the voxels)
    vec4 boxMaxMm;         // xyz: upper corner
    vec4 texFromMmScale;   // xyz: 1 / (dims * spacing); texture coordinate = p * scale + offset
    vec4 texFromMmOffset;  // xyz: 0.5 / dims (voxel centres sit at (i + 0.5) / dims)
    vec4 volumeDims;       // xyz: voxels per axis (float); w: voxels per skipping cell edge
    vec4 invSpacingMm;     // xyz: 1 / spacing
    // Marching
    vec4 march;            // x: base step (mm); y: iso value (HU); z: refinement steps; w: max steps
    vec4 adaptive;         // x: min step; y: max step (mm); z: radians per pixel; w: opacity to stop at
    vec4 transfer;         // x: HU of the first entry; y: (n-1) / (n * HU span); z: reference step (mm); w: 0.5 / n
    vec4 shading;          // x: light falloff (1/mm^2); y: roughness; z: Fresnel F0; w: ambient
    uvec4 frame;           // x, y: image size; z: jitter seed; w: CVC_FLAG_* bits
};

#ifdef __cplusplus
}  // namespace shaders
#endif

#endif  // CVC_HOST_DEVICE_H
