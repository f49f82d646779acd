// The polyline warp: a stereo eye's bent ray marched as up to four straight pieces.
//
// The warp W(q) = c + |q - c| F(dir(q - c)) bends the ray e + t d of an eye at e into the curve
// C(t) = W(e + t d). For the centre eye (e = c) the curve is the straight line c + t F(d), and one
// chord between two of its points is exact. A stereo eye sits |e - c| from the centre (half the
// eye separation at the scene's scale): its curve bends where t is comparable to that offset and
// straightens beyond, approaching a line of direction F(d) at a distance that falls as
// |e - c|^2 / t. The paper's single chord from the near plane to the far end starts on the bent
// part, so it runs beside that line by about |e - c| all the way: on the cabin's map at 10 mm
// per metre its worst distance from the curve beyond 15 mm from the eye is 18.6 pixel footprints
// at the 99th percentile of directions (`cvc_bench polyline`; docs/benchmarks/stereo.md, "Stereo rays:
// the polyline warp"), enough to change a polyp's shape by several per cent.
//
// The polyline's vertices lie on the curve: its near-plane point, the points at t = 4, 14 and 49
// times the eye's offset (a geometric ladder, because the curve's shape scales with the offset),
// and its far end. A ladder vertex is dropped where the curve passes it within
// kPolylineTolerancePixels of the pixel's footprint from the chord joining its neighbours, so a
// ray that the map barely bends keeps fewer pieces (the centre eye one: the chord). Measured the
// same way the worst distance beyond 15 mm becomes 0.16 footprints at the 99th percentile (5 to
// 15 mm: 1.1 against 56), with 3.6 pieces a ray on average.
//
// The march follows the pieces by arc length from the polyline's start, so an empty-space skip
// of s millimetres along it never leaves the ball of radius s it was allowed, across vertices
// too, and a tile's cone bound holds piece by piece (polylineOffsetBound).
#ifndef POLYLINE_WARP_GLSL
#define POLYLINE_WARP_GLSL

const int kMaxPolylinePieces = 4;
// The ladder of the inner vertices, in multiples of the eye's offset from the map centre.
const float kPolylineLadder[kMaxPolylinePieces - 1] = float[](4.0, 14.0, 49.0);
// A ladder vertex this close to the near plane (as a multiple of its distance) is left out: the
// first piece would be too short to matter.
const float kPolylineNearFactor = 1.2;
// How far (in pixel footprints at the vertex, scaled by the map's local scale) the curve may
// pass from a piece before the vertex between them is kept.
const float kPolylineTolerancePixels = 0.05;

// Up to kMaxPolylinePieces pieces: piece k starts at points[k], runs along dirs[k] and ends at
// arc length ends[k] from points[0]; the last piece goes on beyond its end (the far end lies
// outside the volume's box, where the march stops anyway).
struct Polyline {
    vec3 points[kMaxPolylinePieces];
    vec3 dirs[kMaxPolylinePieces];
    float ends[kMaxPolylinePieces];
    int count;
};

// Arc length at which piece k starts.
float pieceStartOf(Polyline line, int k) { return k == 0 ? 0.0 : line.ends[k - 1]; }

float distanceToSegmentMm(vec3 p, vec3 a, vec3 b) {
    vec3 ab = b - a;
    float lengthSquared = dot(ab, ab);
    float f = lengthSquared > 0.0 ? clamp(dot(p - a, ab) / lengthSquared, 0.0, 1.0) : 0.0;
    return length(p - (a + f * ab));
}

// The polyline through `count` vertices (volume millimetres); `fallbackDir` serves pieces too
// short to have a direction (where W folds the ray onto the map centre).
Polyline polylineThrough(vec3 vertices[kMaxPolylinePieces + 1], int count, vec3 fallbackDir) {
    Polyline line;
    line.count = count - 1;
    float arc = 0.0;
    for (int k = 0; k < kMaxPolylinePieces; ++k) {
        if (k >= line.count) {
            line.points[k] = vertices[line.count];
            line.dirs[k] = line.dirs[line.count - 1];
            line.ends[k] = arc;
            continue;
        }
        vec3 piece = vertices[k + 1] - vertices[k];
        float pieceLength = length(piece);
        line.points[k] = vertices[k];
        line.dirs[k] = pieceLength > 1e-6 ? piece / pieceLength : fallbackDir;
        arc += pieceLength;
        line.ends[k] = arc;
    }
    return line;
}

// The polyline of the ray eye + t dir for t in [tNear, tFar] (volume millimetres), bent about
// the map centre. `localScale` is the map's local scale along the pixel's display direction; the
// tolerance is in the footprints of this image's pixels.
Polyline polylineOfRay(vec3 eye, vec3 dir, float tNear, float tFar, float localScale) {
    vec3 vertices[kMaxPolylinePieces + 1];
    float params[kMaxPolylinePieces + 1];
    float offset = length(eye - u.mapCentreMm);
    int count = 0;
    vertices[count] = warpPoint(eye + tNear * dir);
    params[count++] = tNear;
    for (int k = 0; k < kMaxPolylinePieces - 1; ++k) {
        float t = kPolylineLadder[k] * offset;
        if (t > kPolylineNearFactor * tNear && t < tFar) {
            vertices[count] = warpPoint(eye + t * dir);
            params[count++] = t;
        }
    }
    vertices[count] = warpPoint(eye + tFar * dir);
    params[count++] = tFar;
    // Drop, near to far, each inner vertex that lies within the tolerance of the chord from the
    // last vertex kept to the next one.
    int kept = 1;
    for (int k = 1; k < count - 1; ++k) {
        float allowedMm = kPolylineTolerancePixels * params[k] * u.radiansPerPixel * localScale;
        if (distanceToSegmentMm(vertices[k], vertices[kept - 1], vertices[k + 1]) > allowedMm) {
            vertices[kept++] = vertices[k];
        }
    }
    vertices[kept++] = vertices[count - 1];
    return polylineThrough(vertices, kept, dir);
}

// The table's record of a polyline (CVC_POLYLINE_TABLE_BYTES_PER_PIXEL), in the axes and about
// the origin the caller gives: r0 its start and its length; r1 the first piece's octahedral
// direction and length, and the map's local scale; r2 the second piece's direction and length,
// and the third's length; r3 the third and fourth pieces' directions. A piece length of 0 marks
// the piece before it as the last; the last piece's own length is not kept (it runs on).
void recordOfPolyline(Polyline line, mat3 toCave, vec3 centre, float localScale, out vec4 r0, out vec4 r1,
                      out vec4 r2, out vec4 r3) {
    float lengths[kMaxPolylinePieces];
    for (int k = 0; k < kMaxPolylinePieces; ++k) {
        lengths[k] = k < line.count - 1 ? line.ends[k] - pieceStartOf(line, k) : 0.0;
    }
    vec2 octs[kMaxPolylinePieces];
    for (int k = 0; k < kMaxPolylinePieces; ++k) octs[k] = octahedralFromDirection(toCave * line.dirs[k]);
    r0 = vec4(toCave * (line.points[0] - centre), line.ends[line.count - 1]);
    r1 = vec4(octs[0], lengths[0], localScale);
    r2 = vec4(octs[1], lengths[1], lengths[2]);
    r3 = vec4(octs[2], octs[3]);
}

// A record read back as a whole polyline, in the record's own axes (the tile bound's pass).
Polyline polylineOfRecord(vec4 r0, vec4 r1, vec4 r2, vec4 r3) {
    float lengths[kMaxPolylinePieces - 1] = float[](r1.z, r2.z, r2.w);
    vec2 octs[kMaxPolylinePieces] = vec2[](r1.xy, r2.xy, r3.xy, r3.zw);
    Polyline line;
    line.count = 1;
    while (line.count < kMaxPolylinePieces && lengths[line.count - 1] > 0.0) ++line.count;
    vec3 point = r0.xyz;
    float arc = 0.0;
    for (int k = 0; k < kMaxPolylinePieces; ++k) {
        line.dirs[k] = directionFromOctahedral(octs[k]);
        line.points[k] = point;
        bool isLast = k >= line.count - 1;
        float pieceLength = isLast ? 0.0 : lengths[k];
        arc += pieceLength;
        line.ends[k] = isLast ? r0.w : arc;
        point += pieceLength * line.dirs[k];
    }
    return line;
}

// How far polyline p strays from the reference r at equal arc length, as the line alpha + beta t:
// with beta at least the difference of their last pieces' directions, the least alpha such that
// |p(t) - r(t)| <= alpha + beta t for every t >= 0. |p(t) - r(t)| is at most |p(0) - r(0)| plus the
// integral of |p'(s) - r'(s)| up to t, a piecewise linear function whose breakpoints are the two
// polylines' vertices; beyond the last one its slope is the last pieces' difference, at most beta.
// So the line lies above it everywhere once it does at t = 0 and at every breakpoint.
float polylineOffsetBound(Polyline p, Polyline r, float beta) {
    float bound = length(p.points[0] - r.points[0]);
    float alpha = bound;
    float t = 0.0;
    int i = 0, j = 0;
    for (int step = 0; step < 2 * kMaxPolylinePieces && (i < p.count - 1 || j < r.count - 1); ++step) {
        float next = min(i < p.count - 1 ? p.ends[i] : 3.0e38, j < r.count - 1 ? r.ends[j] : 3.0e38);
        bound += length(p.dirs[i] - r.dirs[j]) * (next - t);
        t = next;
        alpha = max(alpha, bound - beta * t);
        if (i < p.count - 1 && p.ends[i] <= t) ++i;
        if (j < r.count - 1 && r.ends[j] <= t) ++j;
    }
    return alpha;
}

#endif
