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
//
// A polyline warp's rays are polylines marched by arc length: the same bound holds with alpha and
// beta from polylineOffsetBound, which follows the pieces of both polylines.
//
// Chords read from the chord table need not be visited: a pose turns and moves all of a tile's
// chords alike, so alpha, beta and the longest chord, measured once in CAVE axes when the table
// is filled (writeTileBound), hold for every frame. The pass then reads one chord and that bound
// per tile, not the tile's 64 chords. The bound covers every chord of the tile, not only those
// that meet the box in this frame, and the cone march starts from t = 0, at or before every
// chord's own start: both can only make the skip shorter.
//
// The pass also decides whether the tile's march looks at the distance map at all. Each look
// runs for the whole vector of rays, and on coarse CT from inside the colon no look finds room
// to skip (a cell needs an empty cell on every side for that): the looks were pure cost there,
// 4-12 % of the frame (docs/benchmarks/march.md). The tile's centre and corner rays are walked cell by
// cell from the tile's start; the looks stay on only if one of them meets an empty cell with
// room to skip (distance 2 or more) before a cell that can contribute. Whatever the answer, a
// march with a fixed step takes the same samples (but for float rounding of where a skip
// lands); only its time changes.
#ifndef RAY_START_GLSL
#define RAY_START_GLSL

layout(constant_id = CVC_SPEC_RAY_START) const int kRayStart = CVC_RAY_START_NONE;
// Per tile: x where its rays' march may start; y 1 where that march looks at the distance map.
layout(std430, binding = CVC_BINDING_RAY_START) buffer RayStartTable { vec2 rayStartTable[]; };

const int kMaxTileSkips = 256;  // cone-marching steps of one tile: ample, and a bound
const int kMaxTileWalkCells = 64;  // cells the look decision walks; undecided after them: looks on

// Radius of a ball around pMm that holds only empty cells: a cell at Chebyshev distance d has
// d - 1 empty cells beyond its own on every side. Less a hundredth of a cell, for the rounding
// by which the march's positions may differ from this pass's.
float emptyRadiusMm(vec3 pMm) {
    uint distanceCells = skipDistanceAt(cellOf(pMm));
    float cellMm = cellVoxels() * minSpacingMm();
    return (float(max(distanceCells, 1u)) - 1.01) * cellMm;
}

// A tile's pixels within the image (tiles at its right and lower edges may be partial) and the
// pixel whose ray is the tile's reference.
struct TilePixels {
    uvec2 first;
    uvec2 last;
    uvec2 centre;
};

bool isTileInImage(uvec2 tile) {
    uvec2 tiles = (u.imageSize + CVC_TILE_SIZE - 1) / CVC_TILE_SIZE;
    return tile.x < tiles.x && tile.y < tiles.y;
}

TilePixels tilePixels(uvec2 tile) {
    TilePixels p;
    p.first = tile * CVC_TILE_SIZE;
    p.last = min(p.first + CVC_TILE_SIZE, u.imageSize) - 1u;
    p.centre = (p.first + p.last) / 2u;
    return p;
}

// A pixel's polyline as the polyline table holds it (CAVE axes about the map centre).
Polyline tablePolylineOf(uvec2 pixel) {
    uint entry = chordTableEntry(pixel);
    return polylineOfRecord(chordTable[entry], chordTable[entry + 1u], chordTable[entry + 2u], chordTable[entry + 3u]);
}

// The chord table's fill, second pass: a tile's cone bound from its chords as the fill wrote
// them (CAVE axes about the map centre), after its pixels in the table.
void writeTileBound(uvec2 tile) {
    if (!isTileInImage(tile)) return;
    TilePixels pixels = tilePixels(tile);
    if (kWarp == CVC_WARP_POLYLINE) {
        // In the table's own axes: the bound holds for every pose, which turns all rays alike.
        Polyline reference = tablePolylineOf(pixels.centre);
        vec3 referenceLast = reference.dirs[reference.count - 1];
        float beta = 0.0;
        float longest = 0.0;
        for (uint y = pixels.first.y; y <= pixels.last.y; ++y) {
            for (uint x = pixels.first.x; x <= pixels.last.x; ++x) {
                Polyline line = tablePolylineOf(uvec2(x, y));
                beta = max(beta, length(line.dirs[line.count - 1] - referenceLast));
                longest = max(longest, line.ends[line.count - 1]);
            }
        }
        float alpha = 0.0;
        for (uint y = pixels.first.y; y <= pixels.last.y; ++y) {
            for (uint x = pixels.first.x; x <= pixels.last.x; ++x) {
                Polyline line = tablePolylineOf(uvec2(x, y));
                alpha = max(alpha, polylineOffsetBound(line, reference, beta));
            }
        }
        chordTable[chordTableBoundEntry(tile)] = vec4(alpha, beta, longest, 0.0);
        return;
    }
    uint centre = chordTableEntry(pixels.centre);
    vec3 referenceStart = chordTable[centre].xyz;
    vec3 referenceDir = directionFromOctahedral(chordTable[centre + 1u].xy);
    float alpha = 0.0;
    float beta = 0.0;
    float longest = 0.0;
    for (uint y = pixels.first.y; y <= pixels.last.y; ++y) {
        for (uint x = pixels.first.x; x <= pixels.last.x; ++x) {
            uint entry = chordTableEntry(uvec2(x, y));
            vec4 direction = chordTable[entry + 1u];
            alpha = max(alpha, length(chordTable[entry].xyz - referenceStart));
            beta = max(beta, length(directionFromOctahedral(direction.xy) - referenceDir));
            longest = max(longest, direction.z);
        }
    }
    chordTable[chordTableBoundEntry(tile)] = vec4(alpha, beta, longest, 0.0);
}

// Whether the march's looks at the distance map can pay along `reference` from t on: walking
// it cell by cell, an empty cell with room to skip comes before a cell that can contribute (or
// the walk runs out of cells before it decides). Leaving the box decides no.
bool isRoomToSkipAhead(Segment reference, float t, float tTo) {
    float nudgeMm = 0.01 * cellVoxels() * minSpacingMm();  // into the next cell, past rounding
    for (int i = 0; i < kMaxTileWalkCells; ++i) {
        if (!(t < tTo)) return false;
        // A polyline, once on the piece that holds t, may have left the box there.
        if (kWarp == CVC_WARP_POLYLINE && !isMarching(reference, t)) return false;
        ivec3 cell = cellOf(reference.origin + t * reference.dir);
        uint distanceCells = skipDistanceAt(cell);
        if (distanceCells >= 2u) return true;
        if (distanceCells == 0u) return false;
        t = max(cellExitT(reference.origin, reference.invDir, cell), t) + nudgeMm;
    }
    return true;
}

// The tile pass: writes tile's entry of the table. A tile none of whose rays meets the box
// gets 0 (its rays do not march anyway), unless its bound came from the chord table.
void writeTileStart(uvec2 tile) {
    if (!isTileInImage(tile)) return;
    TilePixels pixels = tilePixels(tile);
    if (kWarp == CVC_WARP_POLYLINE && kChordTable != CVC_CHORD_TABLE_READ) {
        // Polylines made per ray have no bound at hand (the ray caster does not run this pass
        // for them): every ray marches from its own start and looks at the distance map.
        rayStartTable[tileIndexOf(tile)] = vec2(0.0, 1.0);
        return;
    }
    Segment reference = segmentForPixel(pixels.centre);
    float alpha = 0.0;
    float beta = 0.0;
    float tFrom = 3.0e38;
    float tTo = -3.0e38;
    if (kChordTable == CVC_CHORD_TABLE_READ) {
        vec4 bound = chordTable[chordTableBoundEntry(tile)];
        alpha = bound.x;
        beta = bound.y;
        tFrom = 0.0;      // no chord starts before its own start
        tTo = bound.z;    // nor ends past its length
    } else {
        for (uint y = pixels.first.y; y <= pixels.last.y; ++y) {
            for (uint x = pixels.first.x; x <= pixels.last.x; ++x) {
                Segment s = uvec2(x, y) == pixels.centre ? reference : segmentForPixel(uvec2(x, y));
                if (s.tStart >= s.tEnd) continue;
                alpha = max(alpha, length(s.origin - reference.origin));
                beta = max(beta, length(s.dir - reference.dir));
                tFrom = min(tFrom, s.tStart);
                tTo = max(tTo, s.tEnd);
            }
        }
    }
    float t = tFrom < tTo ? tFrom : 0.0;
    for (int i = 0; i < kMaxTileSkips && t < tTo; ++i) {
        if (kWarp == CVC_WARP_POLYLINE) reference = alongPolylineTo(reference, t);
        float next = (emptyRadiusMm(reference.origin + t * reference.dir) - alpha + t) / (1.0 + beta);
        if (next < t + u.stepMm) break;  // less than a step gained: the march takes it from here
        t = next;
    }
    // The centre ray alone misses the room beside a wall it meets while others pass the wall
    // by (on the yardstick the march then took 11 % more fetches): its four corners' rays too.
    bool isLooking = u.isLookingInEveryTile != 0u || isRoomToSkipAhead(reference, t, tTo);
    uvec2 corners[4] = uvec2[4](pixels.first, pixels.last, uvec2(pixels.first.x, pixels.last.y),
                                uvec2(pixels.last.x, pixels.first.y));
    for (int k = 0; k < 4 && !isLooking; ++k) {
        Segment corner = segmentForPixel(corners[k]);
        isLooking = isRoomToSkipAhead(corner, max(t, corner.tStart), corner.tEnd);
    }
    rayStartTable[tileIndexOf(tile)] = vec2(t, isLooking ? 1.0 : 0.0);
}

// Where the march along s may start: its tile's entry when that lies beyond s.tStart. With a
// fixed step the start stays on the grid of parameters the ray would visit from s.tStart, so
// the samples, and the image, are those of a march from s.tStart.
float rayStartOf(Segment s, uvec2 pixel) {
    if (kRayStart != CVC_RAY_START_READ) return s.tStart;
    float tileStart = rayStartTable[tileIndexOf(pixel / CVC_TILE_SIZE)].x;
    if (!(tileStart > s.tStart)) return s.tStart;
    if (kAdaptive) return tileStart;
    return s.tStart + floor((tileStart - s.tStart) / u.stepMm) * u.stepMm;
}

// Whether the march of the ray through `pixel` looks at the distance map (the tile pass's
// decision; without the pass, always).
bool isLookingInTileOf(uvec2 pixel) {
    if (kRayStart != CVC_RAY_START_READ) return true;
    return rayStartTable[tileIndexOf(pixel / CVC_TILE_SIZE)].y > 0.5;
}

#endif
