#version 450
// The ray caster: one thread per pixel of one wall (or pinhole image) for one eye. A ray is
// built from the eye through the pixel's point on the wall, optionally bent through the
// conformal map, then marched through the volume in iso-surface mode (first crossing of an
// iso value, refined by bisection) or composite mode (transfer function, front-to-back
// blending, early termination). Writes the colour and, on request, the first-hit position.
// A bent ray is marched as one chord (paper Eq. 7), as a polyline through points of the warped
// ray (polyline_warp.glsl: the stereo eyes' default), or by warping every sample (the reference).
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x = CVC_TILE_SIZE, local_size_y = CVC_TILE_SIZE) in;

layout(constant_id = CVC_SPEC_MODE) const int kMode = CVC_MODE_ISO;
layout(constant_id = CVC_SPEC_FILTER) const int kFilter = CVC_FILTER_TRILINEAR;
layout(constant_id = CVC_SPEC_WARP) const int kWarp = CVC_WARP_NONE;
layout(constant_id = CVC_SPEC_SKIPPING) const bool kSkipping = false;
layout(constant_id = CVC_SPEC_ADAPTIVE) const bool kAdaptive = false;
layout(constant_id = CVC_SPEC_COUNT_FETCHES) const bool kCountFetches = false;
layout(constant_id = CVC_SPEC_GRADIENT) const int kGradient = CVC_GRADIENT_BSPLINE;
layout(constant_id = CVC_SPEC_CHORD_TABLE) const int kChordTable = CVC_CHORD_TABLE_NONE;
layout(constant_id = CVC_SPEC_REFINEMENT) const int kRefinementSteps = 2;
layout(constant_id = CVC_SPEC_JITTER) const bool kJitter = false;
layout(constant_id = CVC_SPEC_HIT_OUTPUT) const int kHitOutput = CVC_HIT_OUTPUT_NONE;
layout(constant_id = CVC_SPEC_GRADIENT_VOLUME) const bool kGradientVolume = false;

// Volume fetches this invocation made (only kept when kCountFetches: a benchmark's counter).
uint gFetchCount = 0u;

layout(std140, binding = CVC_BINDING_UNIFORMS) uniform Uniforms { RaycastUniforms u; };
layout(binding = CVC_BINDING_VOLUME) uniform sampler3D volumeTexture;
layout(binding = CVC_BINDING_GRADIENT_VOLUME) uniform sampler3D gradientVolume;
layout(binding = CVC_BINDING_COLOR_IMAGE, rgba8) uniform writeonly image2D colorImage;
layout(binding = CVC_BINDING_HIT_IMAGE, rgba32f) uniform writeonly image2D hitImage;
layout(binding = CVC_BINDING_SKIP_DISTANCE) uniform usampler3D skipDistance;
layout(binding = CVC_BINDING_TRANSFER_FUNCTION) uniform sampler2D transferFunction;
layout(binding = CVC_BINDING_CUBE_MAP) uniform samplerCube cubeMap;
layout(binding = CVC_BINDING_SPEED_BOUND) uniform samplerCube speedBoundMap;
layout(std430, binding = CVC_BINDING_CHORD_TABLE) buffer ChordTable { vec4 chordTable[]; };

#include "ray_box.glsl"
#include "ray_generation.glsl"
#include "polyline_warp.glsl"
#include "jitter.glsl"
#include "volume_sampling.glsl"
#include "transfer_function.glsl"
#include "cook_torrance.glsl"

const vec3 kBackground = vec3(0.015, 0.017, 0.022);
const vec3 kSurfaceColor = vec3(0.93, 0.60, 0.50);  // iso-surface albedo, a mucosa tone
const int kStepsPerSkipCheck = 4;  // plain steps of the march between looks at the empty-space map

// The straight segment a ray marches: origin + t * dir for t in [tStart, tEnd]. In exact-warp
// mode it is the undistorted ray, and every sample point is mapped through W. In polyline mode
// it is the polyline's current piece, with origin and tcOrigin moved along it so that t is the
// arc length from the polyline's start.
struct Segment {
    vec3 origin;
    vec3 dir;
    vec3 tcOrigin;      // the same segment in texture coordinates (not used by exact mode)
    vec3 tcDir;
    float tStart;
    float tEnd;
    float eyeDistance;  // distance from the eye to origin + tStart * dir, minus tStart
    float localScale;   // the map's local scale along this pixel's display direction
    float speedBound;   // exact mode: the map's angular speed bound near the ray's final direction
    vec3 invDir;        // 1 / dir without division by zero (ray_box.glsl), for cell exits
    // Polyline mode: the piece that origin and dir follow, the arc length where it ends (3e38
    // for the last piece, and in other modes), the later pieces as the table holds them (their
    // octahedral directions in CAVE axes and lengths, polyline_warp.glsl: decoded when the march
    // reaches them), and whether tEnd follows the pieces (where the polyline starts in the box).
    int piece;
    float pieceEnd;
    vec4 laterPieces0;
    vec4 laterPieces1;
    bool isEndOnPiece;
};

Segment withTextureRay(Segment s) {
    s.tcOrigin = texFromMm(s.origin);
    s.tcDir = s.dir * u.texFromMmScale;
    s.invDir = safeInverse(s.dir);
    return s;
}

// A tile's index, row by row over the image's tiles (the ray-start table's entry too).
uint tileIndexOf(uvec2 tile) {
    uint tilesPerRow = (u.imageSize.x + CVC_TILE_SIZE - 1) / CVC_TILE_SIZE;
    return tile.y * tilesPerRow + tile.x;
}

// The chord table is laid out tile by tile (each tile's CVC_TILE_SIZE^2 pixels row by row, then
// its cone bound, then the next tile), in the order the work groups run, so that on a CPU
// device a frame reads it as one stream. (Laid out by image rows, a tile's rows would lie a
// wall's width apart, each on a page of its own; docs/benchmarks/warp.md.) The polyline warp's
// table has the same order with four vec4s a pixel.
const uint kChordTableVec4sPerPixel = kWarp == CVC_WARP_POLYLINE ? CVC_POLYLINE_TABLE_BYTES_PER_PIXEL / 16
                                                                 : CVC_CHORD_TABLE_BYTES_PER_PIXEL / 16;
const uint kChordTableVec4sPerTile = CVC_TILE_SIZE * CVC_TILE_SIZE * kChordTableVec4sPerPixel + 1u;

// A pixel's first vec4 in the chord table.
uint chordTableEntry(uvec2 pixel) {
    uvec2 inTile = pixel % CVC_TILE_SIZE;
    uint tile = tileIndexOf(pixel / CVC_TILE_SIZE);
    return tile * kChordTableVec4sPerTile + kChordTableVec4sPerPixel * (inTile.y * CVC_TILE_SIZE + inTile.x);
}

// A tile's cone bound in the chord table (ray_start.glsl), after its pixels' chords.
uint chordTableBoundEntry(uvec2 tile) { return (tileIndexOf(tile) + 1u) * kChordTableVec4sPerTile - 1u; }

// The chord's part inside the box: from its start (or where it enters) to where it leaves, or
// to its far end.
Segment clippedChord(Segment s, float chordLength) {
    vec2 span = intersectBox(s.origin, s.dir, u.boxMinMm, u.boxMaxMm);
    s.tStart = max(span.x, 0.0);
    s.tEnd = min(span.y, chordLength);
    return withTextureRay(s);
}

// A pixel's chord as the fill below wrote it, in CAVE axes about the map centre: this frame's
// pose turns it (caveToVolume) and moves it (mapCentreMm) into the volume. Two 16-byte reads,
// one octahedral decode and two matrix products: the cube-map texels, the near and far points
// and the chord's normalisation were paid for once, when the table was filled.
Segment chordFromTable(uvec2 pixel) {
    uint entry = chordTableEntry(pixel);
    vec4 start = chordTable[entry];            // xyz: the chord's start; w: its distance from the eye
    vec4 direction = chordTable[entry + 1u];   // xy: octahedral direction; z: length; w: local scale
    mat3 toVolume = caveToVolume();
    Segment s;
    s.origin = u.mapCentreMm + toVolume * start.xyz;
    s.dir = toVolume * directionFromOctahedral(direction.xy);
    s.eyeDistance = start.w;
    s.localScale = direction.w;
    s.speedBound = 0.0;
    s.pieceEnd = 3.0e38;
    s.piece = 0;
    s.isEndOnPiece = false;
    return clippedChord(s, direction.z);
}

// Moves s from its piece onto the next, which starts where the current one ends. With tEnd
// following the pieces, the march ends where the new piece leaves the box (or at once, should
// the vertex lie outside it).
Segment onNextPiece(Segment s) {
    int k = s.piece + 1;
    float pieceStart = s.pieceEnd;
    vec3 vertex = s.origin + pieceStart * s.dir;
    vec2 octahedral = k == 1 ? s.laterPieces0.xy : (k == 2 ? s.laterPieces1.xy : s.laterPieces1.zw);
    float pieceLength = k == 1 ? s.laterPieces0.z : (k == 2 ? s.laterPieces0.w : 0.0);
    s.piece = k;
    s.dir = caveToVolume() * directionFromOctahedral(octahedral);
    s.origin = vertex - pieceStart * s.dir;
    s.pieceEnd = pieceLength > 0.0 ? pieceStart + pieceLength : 3.0e38;
    if (s.isEndOnPiece) {
        s.tEnd = isInsideBox(vertex) ? pieceStart + intersectBox(vertex, s.dir, u.boxMinMm, u.boxMaxMm).y : pieceStart;
    }
    return withTextureRay(s);
}

// Moves s onto the piece that holds arc length t (at or after its current piece).
Segment alongPolylineTo(Segment s, float t) {
    for (int k = 1; k < kMaxPolylinePieces && t > s.pieceEnd; ++k) s = onNextPiece(s);
    return s;
}

// A polyline's segment from its record (polyline_warp.glsl; CAVE axes about the map centre),
// turned into this frame, on its first piece. Where it starts inside the box (the eye inside the
// volume), the march begins at its start and tEnd follows the pieces; else the first stretch
// inside the box is found piece by piece.
Segment polylineFromRecord(vec4 r0, vec4 r1, vec4 r2, vec4 r3, float eyeDistance) {
    mat3 toVolume = caveToVolume();
    Segment s;
    s.origin = u.mapCentreMm + toVolume * r0.xyz;
    s.dir = toVolume * directionFromOctahedral(r1.xy);
    s.piece = 0;
    s.pieceEnd = r1.z > 0.0 ? r1.z : 3.0e38;
    s.localScale = r1.w;
    s.laterPieces0 = r2;
    s.laterPieces1 = r3;
    s.eyeDistance = eyeDistance;
    s.speedBound = 0.0;
    s = withTextureRay(s);
    if (isInsideBox(s.origin)) {
        s.tStart = 0.0;
        s.tEnd = intersectBox(s.origin, s.dir, u.boxMinMm, u.boxMaxMm).y;
        s.isEndOnPiece = true;
        return s;
    }
    s.isEndOnPiece = false;
    s.tStart = 1.0;
    s.tEnd = 0.0;
    Segment walker = s;
    bool isInside = false;
    float pieceStart = 0.0;
    for (int k = 0; k < kMaxPolylinePieces; ++k) {
        if (k > 0) {
            if (walker.pieceEnd >= 3.0e38) break;  // that was the last piece
            pieceStart = walker.pieceEnd;
            walker = onNextPiece(walker);
        }
        vec2 span = intersectBox(walker.origin, walker.dir, u.boxMinMm, u.boxMaxMm);  // in arc length
        float from = max(span.x, pieceStart), to = min(span.y, walker.pieceEnd);
        if (!(from <= to)) {
            if (isInside) break;  // left the box at the last piece's end
            continue;
        }
        if (!isInside) {
            s.tStart = from;
            isInside = true;
        } else if (from > s.tEnd) {
            break;  // left the box before this piece came back into it
        }
        s.tEnd = to;
        if (to < walker.pieceEnd) break;  // leaves the box on this piece
    }
    return s;
}

// A pixel's polyline from the table, turned into this frame.
Segment polylineFromTable(uvec2 pixel) {
    uint entry = chordTableEntry(pixel);
    vec3 dir = normalize(wallPointMm(pixel) - u.eyeMm);
    float eyeDistance = u.nearMm / max(dot(dir, u.wallNormal), 1e-3);  // segmentForPixel's tNear
    return polylineFromRecord(chordTable[entry], chordTable[entry + 1u], chordTable[entry + 2u],
                              chordTable[entry + 3u], eyeDistance);
}

// Whether the march along s goes on at t: for a polyline, once s is on the piece that holds t.
bool isMarching(inout Segment s, float t) {
    if (kWarp == CVC_WARP_POLYLINE && t > s.pieceEnd) s = alongPolylineTo(s, t);
    return t <= s.tEnd;
}

Segment segmentForPixel(uvec2 pixel) {
    if (kChordTable == CVC_CHORD_TABLE_READ) {
        return kWarp == CVC_WARP_POLYLINE ? polylineFromTable(pixel) : chordFromTable(pixel);
    }
    vec3 eye = u.eyeMm;
    vec3 wallPoint = wallPointMm(pixel);
    vec3 dir = normalize(wallPoint - eye);
    // The near plane is parallel to the wall, u.nearMm in front of the eye.
    float tNear = u.nearMm / max(dot(dir, u.wallNormal), 1e-3);

    Segment s;
    s.localScale = 1.0;
    s.speedBound = 0.0;
    s.eyeDistance = 0.0;
    s.pieceEnd = 3.0e38;
    s.piece = 0;
    s.isEndOnPiece = false;
    if (kWarp == CVC_WARP_NONE) {
        vec2 span = intersectBox(eye, dir, u.boxMinMm, u.boxMaxMm);
        s.origin = eye;
        s.dir = dir;
        s.tStart = max(span.x, tNear);
        s.tEnd = span.y;
        return withTextureRay(s);
    }
    // The far point lies beyond every point of the box seen from the map centre (the reach is
    // the box's diagonal plus the centre's distance from the box), so the bent ray reaches the
    // far side of the box whichever way the map turns it. The reach depends on the volume, not
    // on the pose (while the centre is inside the box), so the chord table stays valid.
    vec3 c = u.mapCentreMm;
    float tFar = u.chordReachMm + length(eye - c) + tNear;
    // Only the adaptive step and the polyline's tolerance read the map's local scale (and the
    // table keeps it): other variants save the fetch.
    if (kAdaptive || kChordTable == CVC_CHORD_TABLE_FILL || kWarp == CVC_WARP_POLYLINE) {
        s.localScale = sceneFromDisplay(normalize(wallPoint - c)).w;
    }
    if (kWarp == CVC_WARP_EXACT) {
        // The direction of a ray's point seen from the map centre turns toward dir as the ray
        // goes on: the bound near dir serves its skips (skipAlongBentRay).
        if (kSkipping) s.speedBound = textureLod(speedBoundMap, transpose(caveToVolume()) * dir, 0.0).r;
        s.origin = eye;
        s.dir = dir;
        s.tStart = tNear;
        s.tEnd = tFar;
        return s;
    }
    if (kWarp == CVC_WARP_POLYLINE) {
        // Recorded as the table records it (CAVE axes about the map centre, the same for every
        // pose, as the chord's below), so a polyline made per ray is marched as one read.
        vec4 r0, r1, r2, r3;
        recordOfPolyline(polylineOfRay(eye, dir, tNear, tFar, s.localScale), transpose(caveToVolume()), c,
                         s.localScale, r0, r1, r2, r3);
        if (kChordTable == CVC_CHORD_TABLE_FILL) {
            uint entry = chordTableEntry(pixel);
            chordTable[entry] = r0;
            chordTable[entry + 1u] = r1;
            chordTable[entry + 2u] = r2;
            chordTable[entry + 3u] = r3;
            s.tStart = 1.0;
            s.tEnd = 0.0;
            return s;
        }
        return polylineFromRecord(r0, r1, r2, r3, tNear);
    }
    // Chord mode (paper Eq. 7): map the near and far points, march the chord between them.
    vec3 a = warpPoint(eye + tNear * dir);
    vec3 b = warpPoint(eye + tFar * dir);
    float chordLength = length(b - a);
    s.origin = a;
    s.dir = chordLength > 1e-6 ? (b - a) / chordLength : dir;
    s.eyeDistance = tNear;
    if (kChordTable == CVC_CHORD_TABLE_FILL) {
        // The chord in CAVE axes about the map centre, which do not depend on the pose. (The
        // host fills the table from the display's own geometry, given in those axes about a
        // centre at the origin, so that the table does not depend on which frame filled it.)
        mat3 toCave = transpose(caveToVolume());
        uint entry = chordTableEntry(pixel);
        chordTable[entry] = vec4(toCave * (a - c), tNear);
        chordTable[entry + 1u] = vec4(octahedralFromDirection(toCave * s.dir), chordLength, s.localScale);
        s.tStart = 1.0;
        s.tEnd = 0.0;
        return s;
    }
    return clippedChord(s, chordLength);
}

vec3 pointAt(Segment s, float t) {
    vec3 p = s.origin + t * s.dir;
    return kWarp == CVC_WARP_EXACT ? warpPoint(p) : p;
}

// HU at ray parameter t; points an exact-warped ray bends outside the box read as air. A
// straight segment steps in texture coordinates directly: one multiply-add per sample.
float valueAt(Segment s, float t) {
    if (kWarp != CVC_WARP_EXACT) return huFromUnorm(fetchFiltered(s.tcOrigin + t * s.tcDir));
    vec3 p = pointAt(s, t);
    if (!isInsideBox(p)) return -32768.0;
    return sampleHu(p);
}

float minSpacingMm() {
    vec3 spacing = 1.0 / u.invSpacingMm;
    return min(min(spacing.x, spacing.y), spacing.z);
}

#include "empty_space.glsl"
#include "ray_start.glsl"

// Step length at t: the base step, lengthened where one pixel covers more than a voxel (far
// away, or where the map compresses the scene), within [min step, max step].
float stepAt(Segment s, float t) {
    if (!kAdaptive) return u.stepMm;
    float footprintMm = (t + s.eyeDistance) * u.radiansPerPixel * s.localScale;
    return clamp(u.stepMm * max(1.0, footprintMm / minSpacingMm()), u.minStepMm, u.maxStepMm);
}

// Empty-space skipping: once t has left the cell last looked up, reads the distance map at t.
// At a distance of d > 1 cells, everything within (d - 1) cells is empty: t moves to the last
// sample position that stays inside that range, and the function returns true. With a fixed
// step the new t stays on the grid of t's an unskipped ray visits, so the image does not
// change; tPrev becomes the grid point before it, which lies in empty space. Near matter the
// map is not read again before the ray leaves the cell. (Moving t to where the ray leaves the
// empty cube of 2d - 1 cells instead, as Chebyshev distance maps allow, took 11 % fewer fetches
// on the yardstick but 11 % more time: more of the looks, which run for the whole vector of
// rays, found nothing; docs/benchmarks/march.md.)
//
// An exact-warped ray is bent at every sample: its scene point W(q), q = o + t d, moves at most
// (1 + L) mm per mm of t. The radius |q - c| changes by at most 1 mm, and the direction of
// q - c turns by at most 1 / |q - c| radians per mm, which the map turns into at most L / |q - c|
// (L: the map's angular speed bound). The ball the distance map leaves empty around W(q) then
// holds the next R / (1 + L) mm of the ray. L comes from the coarse bound map near d, and holds
// while the direction of q - c stays within the bound's reach of d: from a point where it does,
// it only turns further toward d. Near the map's singular points L is large and the skips
// shrink to nothing, as they should. A bent ray has no straight cell exit, and a look costs a
// map fetch of its own: after each look that finds no skip the next waits twice as many steps
// (from kStepsPerSkipCheck up to kMaxBentSkipWait), and a skip starts the waits afresh.
const float kMaxBentSkipWait = 64.0;

bool skipAlongBentRay(Segment s, inout float tCheck, inout float wait, inout float t, inout float tPrev) {
    float step = stepAt(s, t);
    vec3 fromCentre = s.origin + t * s.dir - u.mapCentreMm;
    float radius = length(fromCentre);
    float steps = 0.0;
    if (radius > 1e-6 && dot(fromCentre, s.dir) >= u.speedBoundCosReach * radius) {
        vec3 p = pointAt(s, t);
        float freeMm = float(max(skipDistanceAt(cellOf(p)), 1u) - 1u) * cellVoxels() * minSpacingMm();
        steps = floor(freeMm / ((1.0 + s.speedBound) * step));
    }
    if (steps < 1.0) {
        tCheck = t + (wait - 0.5) * step;
        wait = min(2.0 * wait, kMaxBentSkipWait);
        return false;
    }
    t += steps * step;
    tPrev = t - step;
    wait = float(kStepsPerSkipCheck);
    return true;
}

// `wait` is the exact warp's: the steps its next fruitless look waits (skipAlongBentRay).
bool skipEmptySpace(Segment s, inout float tCheck, inout float wait, inout float t, inout float tPrev) {
    if (!kSkipping || t < tCheck) return false;
    if (kWarp == CVC_WARP_EXACT) return skipAlongBentRay(s, tCheck, wait, t, tPrev);
    ivec3 cell = cellOf(s.origin + t * s.dir);
    uint distanceCells = skipDistanceAt(cell);
    float step = stepAt(s, t);
    float freeMm = float(max(distanceCells, 1u) - 1u) * cellVoxels() * minSpacingMm();
    float steps = floor(freeMm / step);
    if (steps < 1.0) {
        tCheck = cellExitT(s.origin, s.invDir, cell);
        return false;
    }
    t += steps * step;
    tPrev = t - step;
    return true;
}

// Below this gradient a sample lies in homogeneous material, where the gradient's direction is
// float rounding, not a surface: it is shaded as if facing the eye. (CT noise alone gives tens
// of HU per mm; a tissue boundary hundreds.)
const float kFlatGradientHuPerMm = 0.5;

vec3 normalAt(vec3 p, vec3 towardEye) {
    bool isBSpline = kGradient == CVC_GRADIENT_BSPLINE || kFilter == CVC_FILTER_TRICUBIC;
    vec3 g = kGradientVolume ? gradientFromVolumeHu(p, isBSpline) : gradientCentralHu(p, isBSpline);
    float gLength = length(g);
    return gLength > kFlatGradientHuPerMm ? -g / gLength : towardEye;
}

// The direction in which the ray arrives at its point p = pointAt(s, t), reversed: where the
// viewer's headlight and line of sight come from. A bent ray arrives along its own tangent, not
// from where the eye sits: the exact warp's tangent is taken from the mapped point half a step
// back; the chord's and the polyline's pieces are their tangents.
vec3 towardEyeAt(Segment s, float t, vec3 p) {
    if (kWarp != CVC_WARP_EXACT) return -s.dir;
    vec3 back = pointAt(s, t - 0.5 * u.stepMm) - p;
    float backLength = length(back);
    return backLength > 1e-6 ? back / backLength : normalize(u.eyeMm - p);
}

void main() {
    if (kRayStart == CVC_RAY_START_FILL) {  // one invocation per tile; no image is written
        if (kChordTable == CVC_CHORD_TABLE_FILL) {
            writeTileBound(gl_GlobalInvocationID.xy);
        } else {
            writeTileStart(gl_GlobalInvocationID.xy);
        }
        return;
    }
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= u.imageSize.x || pixel.y >= u.imageSize.y) return;

    Segment s = segmentForPixel(pixel);
    if (kChordTable == CVC_CHORD_TABLE_FILL) return;  // the table is written; no image is
    float tOwnStart = s.tStart;
    s.tStart = rayStartOf(s, pixel);
    if (kWarp == CVC_WARP_POLYLINE) s = alongPolylineTo(s, s.tStart);
    float tFirst = -1.0;  // the first sample that contributes (for CVC_HIT_OUTPUT_RAY_STARTS)
    // Fraction of a step by which the first sample is offset; 0 without jitter.
    float jitter = kJitter ? jitterFraction(pixel, u.jitterSeed) : 0.0;
    int maxSteps = int(u.maxSteps);
    float iso = u.isoHu;

    // Whether the march looks at the distance map: not where the tile pass found that the looks
    // would find nothing to skip.
    bool isLooking = kSkipping && isLookingInTileOf(pixel);

    vec3 color = kBackground;
    vec4 hit = vec4(0.0);
    if (s.tStart < s.tEnd) {
        float tCheck = isLooking ? -1.0 : 3.0e38;  // read the distance map at the first sample, or never
        float skipWait = float(kStepsPerSkipCheck);
        float tPrev = s.tStart;
        float t = s.tStart;
        if (kMode == CVC_MODE_ISO) {
            // The march only fetches, compares and advances: on a SIMD CPU device a branch's body
            // runs for the whole vector of rays whenever one of them takes it, so the hit's
            // refinement waits until after the loop, where every ray that hit does it together.
            float vStart = valueAt(s, t);
            bool isHit = vStart >= iso;  // the ray starts inside matter: hit where it enters
            bool isInside = isHit;
            float vPrev = vStart;        // the value at tPrev, unless a skip moved tPrev
            bool isPrevKnown = true;
            float vHit = vStart;
            t += (jitter > 0.0 ? jitter : 1.0) * stepAt(s, t);  // tStart itself was just sampled
            for (int i = 0; i < maxSteps && !isHit && isMarching(s, t);) {
                if (skipEmptySpace(s, tCheck, skipWait, t, tPrev)) {
                    isPrevKnown = false;
                    ++i;
                    continue;
                }
                // Up to kStepsPerSkipCheck plain steps before the distance map is looked at again:
                // its lookup and cell arithmetic run for the whole vector whenever one ray needs
                // them, so they are paid once per chunk, not once per step.
                // (A polyline's march moves onto its next piece in isMarching: rare for a ray,
                // so the vector pays it a few times per march.)
                for (int k = 0; k < kStepsPerSkipCheck && !isHit && isMarching(s, t); ++k, ++i) {
                    float value = valueAt(s, t);
                    isHit = value >= iso;
                    if (!isHit) {
                        tPrev = t;
                        vPrev = value;
                        isPrevKnown = true;
                        t += stepAt(s, t);
                    }
                    vHit = value;
                }
            }
            if (isHit) {
                float tHit = isInside ? s.tStart : t;
                if (!isInside && kRefinementSteps > 0) {
                    // The crossing lies in (tPrev, t]: bisect, keeping lo below and hi at or above
                    // the iso value, then interpolate linearly between their known values. (Where a
                    // polyline's vertex lies in that step, its part before the vertex is read on the
                    // next piece's line: off the polyline by the step times the angle between the
                    // pieces, hundredths of a millimetre.)
                    float lo = tPrev, hi = t;
                    float vLo = isPrevKnown ? vPrev : valueAt(s, lo);  // after a skip: one fetch
                    float vHi = vHit;
                    for (int b = 0; b < kRefinementSteps; ++b) {
                        float mid = 0.5 * (lo + hi);
                        float vMid = valueAt(s, mid);
                        if (vMid >= iso) {
                            hi = mid;
                            vHi = vMid;
                        } else {
                            lo = mid;
                            vLo = vMid;
                        }
                    }
                    float f = vHi > vLo ? clamp((iso - vLo) / (vHi - vLo), 0.0, 1.0) : 1.0;
                    tHit = mix(lo, hi, f);
                }
                tFirst = tHit;
                vec3 p = pointAt(s, tHit);
                vec3 towardEye = towardEyeAt(s, tHit, p);
                vec3 normal = normalAt(p, towardEye);
                color = shadeCookTorrance(normal, towardEye, tHit + s.eyeDistance, kSurfaceColor);
                hit = vec4(kHitOutput == CVC_HIT_OUTPUT_NORMAL ? normal : p, 1.0);
            }
        } else {
            // Composite: front-to-back "over" blending of classified, shaded samples.
            vec4 accumulated = vec4(0.0);
            t += jitter * stepAt(s, t);
            bool isOpaque = false;
            for (int i = 0; i < maxSteps && !isOpaque && isMarching(s, t);) {
                if (skipEmptySpace(s, tCheck, skipWait, t, tPrev)) {
                    ++i;
                    continue;
                }
                // As in the iso march, the distance map is looked at once per chunk of plain
                // steps, not before every sample (7 % of the yardstick's composite time).
                for (int k = 0; k < kStepsPerSkipCheck && !isOpaque && isMarching(s, t); ++k, ++i) {
                    float step = stepAt(s, t);
                    vec3 p = pointAt(s, t);
                    float value = valueAt(s, t);
                    // The table's fetch only where the value can be visible: on lavapipe a branch
                    // that no ray of the vector takes is passed over, and most samples are air.
                    vec4 sampleColor = vec4(0.0);
                    if (isPossiblyVisible(value)) sampleColor = classify(value, step);
                    if (sampleColor.a > 1.0 / 1024.0) {
                        if (tFirst < 0.0) tFirst = t;
                        // Gradients only for samples that contribute.
                        vec3 towardEye = towardEyeAt(s, t, p);
                        vec3 normal = normalAt(p, towardEye);
                        vec3 shaded = shadeCookTorrance(normal, towardEye, t + s.eyeDistance, sampleColor.rgb);
                        accumulated.rgb += (1.0 - accumulated.a) * sampleColor.a * shaded;
                        accumulated.a += (1.0 - accumulated.a) * sampleColor.a;
                        if (hit.w == 0.0 && accumulated.a >= 0.5) {
                            hit = vec4(kHitOutput == CVC_HIT_OUTPUT_NORMAL ? normal : p, 1.0);
                        }
                        isOpaque = accumulated.a >= u.opacityToStop;  // early ray termination
                    }
                    tPrev = t;
                    t += step;
                }
            }
            color = accumulated.rgb + (1.0 - accumulated.a) * kBackground;
        }
    }
    imageStore(colorImage, ivec2(pixel), vec4(pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0));
    if (kHitOutput == CVC_HIT_OUTPUT_RAY_STARTS) {
        float flags = (tFirst >= 0.0 ? CVC_RAY_STARTS_CONTRIBUTES : 0.0);
        if (isLooking) flags += CVC_RAY_STARTS_LOOKS;
        hit = vec4(tOwnStart, s.tStart, tFirst, flags);
    }
    if (kCountFetches) hit.w = float(gFetchCount);
    if (kHitOutput != CVC_HIT_OUTPUT_NONE) imageStore(hitImage, ivec2(pixel), hit);
}
