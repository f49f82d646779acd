/// @brief Structures and binding numbers shared by the C++ host code and the GLSL shaders.
///
/// Included from C++ (with GLM types) and from GLSL (with its built-in types), so both sides
/// agree on every offset. Only vec4-sized members are used: std140 and C++ then lay them
/// out identically (checked by static_asserts in engine/raycast_uniforms.h).
#ifndef CVC_HOST_DEVICE_H
#define CVC_HOST_DEVICE_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace shaders {
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
#endif

// Bindings of the iso-surface raycaster (shaders/raycast_iso.comp).
#define CVC_BINDING_UNIFORMS 0
#define CVC_BINDING_VOLUME 1
#define CVC_BINDING_COLOR_IMAGE 2
#define CVC_BINDING_HIT_IMAGE 3

// Work-group size of the image-space shaders (pixels per group along x and y).
#define CVC_TILE_SIZE 8

/// Everything one ray-casting dispatch needs, in volume millimetres (see volumes/volume.h).
struct RaycastUniforms {
    vec4 eyeMm;            // xyz: camera position; w: unused
    vec4 forward;          // xyz: unit view direction
    vec4 rightScaled;      // xyz: camera right * tan(fovX / 2)
    vec4 upScaled;         // xyz: camera up * tan(fovY / 2)
    vec4 boxMinMm;         // xyz: lower corner of the volume's box (outer faces of the voxels)
    vec4 boxMaxMm;         // xyz: upper corner
    vec4 texFromMmScale;   // xyz: 1 / (dims * spacing); texture coordinate = p * scale + offset
    vec4 texFromMmOffset;  // xyz: 0.5 / dims (voxel centres sit at (i + 0.5) / dims)
    vec4 voxelStepTex;     // xyz: one voxel in texture coordinates (for gradients); w: unused
    vec4 invSpacingMm;     // xyz: 1 / spacing (gradients in HU per mm); w: unused
    vec4 march;            // x: step (mm); y: iso value (HU); z: bisection steps; w: max steps
    uvec4 imageSize;       // x, y: output size in pixels
};

#ifdef __cplusplus
}  // namespace shaders
#endif

#endif  // CVC_HOST_DEVICE_H
