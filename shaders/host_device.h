/// @brief Structures, binding numbers and specialization constants shared by the C++ host code
/// and the GLSL shaders.
///
/// Included from C++ (with GLM types) and from GLSL (with its built-in types), so both sides
/// agree on every offset (checked by tests/engine/uniform_layout_test.cpp against glslang's
/// reflection of the compiled shader).
#ifndef CVC_HOST_DEVICE_H
#define CVC_HOST_DEVICE_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace shaders {
using vec3 = glm::vec3;
using uvec2 = glm::uvec2;
using uint = std::uint32_t;
#endif

// Bindings of the ray caster (shaders/raycast.comp).
#define CVC_BINDING_UNIFORMS 0
#define CVC_BINDING_VOLUME 1
#define CVC_BINDING_COLOR_IMAGE 2
#define CVC_BINDING_HIT_IMAGE 3
#define CVC_BINDING_SKIP_DISTANCE 4  // the empty-space distance map
#define CVC_BINDING_TRANSFER_FUNCTION 5
#define CVC_BINDING_CUBE_MAP 6
#define CVC_BINDING_CHORD_TABLE 7  // per pixel, its chord in CAVE axes (CVC_CHORD_TABLE_*)
#define CVC_BINDING_RAY_START 8    // per tile, where its rays' march may start (shaders/ray_start.glsl)
#define CVC_BINDING_SPEED_BOUND 9  // coarse cube map: how fast the map may turn an exact-warped ray
#define CVC_BINDING_GRADIENT_VOLUME 10  // each voxel's central differences (engine/render/gradient_volume.h)

// Specialization constants: choices fixed per pipeline, so a variant carries no code (and no
// fetches) for features it does not use.
#define CVC_SPEC_MODE 0        // CVC_MODE_*
#define CVC_SPEC_FILTER 1      // CVC_FILTER_*
#define CVC_SPEC_WARP 2        // CVC_WARP_*
#define CVC_SPEC_SKIPPING 3    // 1: empty-space skipping over bricks
#define CVC_SPEC_ADAPTIVE 4    // 1: adaptive step size
#define CVC_SPEC_COUNT_FETCHES 5  // 1: hit image w = texture fetches the ray made (benchmarks)
#define CVC_SPEC_GRADIENT 6    // CVC_GRADIENT_*: how shading normals are computed
#define CVC_SPEC_CHORD_TABLE 7 // CVC_CHORD_TABLE_*: where chord mode gets its cube-map texels
#define CVC_SPEC_RAY_START 8   // CVC_RAY_START_*: the tile pass that skips empty space before marching
#define CVC_SPEC_REFINEMENT 9  // iso mode: bisection steps of a hit (a constant loop bound unrolls)
#define CVC_SPEC_JITTER 10     // 1: offset each ray's first sample by a hash of pixel and RaycastUniforms::jitterSeed
#define CVC_SPEC_HIT_OUTPUT 11 // CVC_HIT_OUTPUT_*: what the hit image receives
#define CVC_SPEC_GRADIENT_VOLUME 12  // 1: shading gradients read from the gradient volume, not from the volume's taps

#define CVC_MODE_ISO 0
#define CVC_MODE_COMPOSITE 1
#define CVC_FILTER_TRILINEAR 0
#define CVC_FILTER_TRICUBIC 1
#define CVC_WARP_NONE 0
#define CVC_WARP_CHORD 1   // map the near and far ends of the ray, march the chord (paper Eq. 7)
#define CVC_WARP_EXACT 2   // map every sample (the reference for stereo eyes)
#define CVC_WARP_POLYLINE 3  // march a polyline through mapped points of the ray (shaders/polyline_warp.glsl)
#define CVC_GRADIENT_CENTRAL 0  // central differences of the filtered volume (6 trilinear fetches)
#define CVC_GRADIENT_BSPLINE 1  // central differences of the cubic B-spline interpolant (48 fetches, smooth)
// A pixel's chord, in CAVE axes about the map centre, depends only on the display, the eye and
// the scale, not on the pose: it can be made once and turned into every later frame's pose.
#define CVC_CHORD_TABLE_NONE 0  // make each chord per ray (two cube-map fetches)
#define CVC_CHORD_TABLE_READ 1  // read the chords from the chord table
#define CVC_CHORD_TABLE_FILL 2  // make the chords and write the chord table; no ray is marched
// The table, tile by tile: per pixel two vec4s, the chord in CAVE axes about the map centre: its
// start and its distance from the eye; its direction as octahedral coordinates, its length and
// the map's local scale along the pixel (for the adaptive step). After a tile's pixels one vec4,
// its cone bound: how far its chords' starts and directions lie from its centre pixel's, and its
// longest chord (shaders/ray_start.glsl), which the tile pass reads in place of every chord.
#define CVC_CHORD_TABLE_BYTES_PER_PIXEL 32
#define CVC_CHORD_TABLE_BYTES_PER_TILE (CVC_TILE_SIZE * CVC_TILE_SIZE * CVC_CHORD_TABLE_BYTES_PER_PIXEL + 16)
// The polyline warp's table has the same order, four vec4s a pixel (shaders/polyline_warp.glsl):
// the polyline's start and its length; its first piece's octahedral direction, length and the
// map's local scale; the second piece's direction and length, and the third's length; the third
// and fourth pieces' directions. The tile's cone bound follows as in the chord table.
#define CVC_POLYLINE_TABLE_BYTES_PER_PIXEL 64
#define CVC_POLYLINE_TABLE_BYTES_PER_TILE (CVC_TILE_SIZE * CVC_TILE_SIZE * CVC_POLYLINE_TABLE_BYTES_PER_PIXEL + 16)
// A pass over the image's tiles (one invocation per CVC_TILE_SIZE^2 pixels) writes, per tile, a
// ray parameter before which every ray of the tile crosses only empty cells; the march reads it.
#define CVC_RAY_START_NONE 0  // rays start where they enter the box
#define CVC_RAY_START_READ 1  // rays start at their tile's entry of the ray-start table
#define CVC_RAY_START_FILL 2  // the tile pass: write the table; no ray is marched

// The hit image, per pixel: xyz as below, w 1 where the ray hit (0 where it missed).
#define CVC_HIT_OUTPUT_NONE 0      // no hit image is written
#define CVC_HIT_OUTPUT_POSITION 1  // the first hit's position, volume mm
#define CVC_HIT_OUTPUT_NORMAL 2    // tests: the shading normal at the first hit
// Tests: ray parameters instead of the position: x the ray's own start, y its start after the
// tile pass, z the first sample that contributes (iso: the refined hit); w the sum of the flags
// below.
#define CVC_HIT_OUTPUT_RAY_STARTS 3
#define CVC_RAY_STARTS_CONTRIBUTES 1.0  // a sample of the ray contributes
#define CVC_RAY_STARTS_LOOKS 2.0        // the ray's march looks at the distance map

// Work-group size of the image-space shaders (pixels per group along x and y).
#define CVC_TILE_SIZE 8

/// Everything one ray-casting dispatch needs. Positions and lengths are in volume millimetres
/// (voxel (i, j, k) centred at (i, j, k) * spacing, see volumes/volume.h). Each vec3 starts a
/// 16-byte slot and the scalar after it fills the slot: std140 and C++ then agree on every
/// offset, which a test checks against the compiled shader's own reflection.
struct RaycastUniforms {
    // Rays: pixel (x, y) looks from the eye through wallOrigin + (x+.5)/w * wallU + (y+.5)/h * wallV.
    vec3 eyeMm;            float nearMm;            // near plane: this far from the eye along wallNormal
    vec3 wallOriginMm;     float stepMm;            // corner at pixel (0, 0)'s outer corner (top left); base step
    vec3 wallUMm;          float isoHu;             // the image's full width, left to right; iso value
    vec3 wallVMm;          float speedBoundCosReach;  // full height, top to bottom; exact warp: where the speed bound holds
    vec3 wallNormal;       float maxSteps;          // unit normal of the image plane, away from the eye; step bound
    // Warp W(q) = c + |q - c| R F(R^T dir(q - c)) (paper Eq. 7), in volume millimetres.
    vec3 mapCentreMm;      float minStepMm;         // c, the map centre (the CAVE's centre); adaptive step bounds
    vec3 caveToVolume0;    float maxStepMm;         // R's columns: the CAVE's x, y, z axes as unit volume vectors
    vec3 caveToVolume1;    float radiansPerPixel;   // ... the adaptive step's pixel footprint
    vec3 caveToVolume2;    float opacityToStop;     // ... composite mode's early ray termination
    // Volume
    vec3 boxMinMm;         float transferFirstHu;   // the box's lower corner (outer faces of the voxels)
    vec3 boxMaxMm;         float transferIndexPerHu;  // upper corner; (n - 1) / (n * HU span) of the table
    vec3 texFromMmScale;   float transferReferenceStepMm;  // 1 / (dims * spacing): tc = p * scale + offset
    vec3 texFromMmOffset;  float transferHalfEntry; // 0.5 / dims (voxel centres at (i + 0.5) / dims); 0.5 / n
    vec3 volumeDims;       float skipCellVoxels;    // voxels per axis; voxels per empty-space cell edge
    vec3 invSpacingMm;     float lightFalloffPerMm2;  // 1 / spacing; headlight falloff 1 / half distance^2
    // Shading (Cook-Torrance) and the frame
    float roughness;       float fresnelF0;         float ambient;           float chordReachMm;  // a bent ray's far end lies this far beyond the near plane and the eye's offset from c
    uvec2 imageSize;       float transferVisibleFromHu;  float transferVisibleToHu;  // composite: zero opacity outside (from, to)
    uint jitterSeed;       uint isLookingInEveryTile;  uint padding1;        uint padding2;  // 1: the tile pass keeps every tile's march looks; padding fills the slot
};

#ifdef __cplusplus
}  // namespace shaders
#endif

#endif  // CVC_HOST_DEVICE_H
