// Rays from display walls (or a pinhole camera's image plane) and the warp of space that bends
// them through the conformal map (paper Eq. 7).
#ifndef RAY_GENERATION_GLSL
#define RAY_GENERATION_GLSL

// The point of pixel (x, y)'s centre on the wall (or image plane), volume millimetres.
vec3 wallPointMm(uvec2 pixel) {
    vec2 uv = (vec2(pixel) + 0.5) / vec2(u.imageSize);
    return u.wallOriginMm + uv.x * u.wallUMm + uv.y * u.wallVMm;
}

mat3 caveToVolume() { return mat3(u.caveToVolume0, u.caveToVolume1, u.caveToVolume2); }

// The cube map's texel for the display direction of point q (volume millimetres) seen from
// the map centre: xyz = F of that direction in CAVE axes (not normalised), w = the map's local
// scale there. At the centre itself, whose direction is undefined, any texel will do.
vec4 cubeTexelAt(vec3 qMm) {
    vec3 offset = qMm - u.mapCentreMm;
    float radius = length(offset);
    vec3 display = radius < 1e-6 ? vec3(0.0, -1.0, 0.0) : offset / radius;
    return textureLod(cubeMap, transpose(caveToVolume()) * display, 0.0);
}

// F for a display direction given in volume axes: xyz = the scene direction in volume axes,
// w = the map's local scale there (scene radians per display radian). The cube map holds F in
// CAVE axes, so the direction is turned into the CAVE frame and the answer back.
vec4 sceneFromDisplay(vec3 displayDirVolume) {
    mat3 toVolume = caveToVolume();
    vec4 texel = textureLod(cubeMap, transpose(toVolume) * displayDirVolume, 0.0);
    return vec4(toVolume * normalize(texel.xyz), texel.w);
}

// A unit vector as octahedral coordinates in [-1, 1]^2 (the sphere folded onto the octahedron
// |x| + |y| + |z| = 1 and unfolded onto a square), and back: two floats for a direction, exact
// to float rounding.
vec2 octahedralFromDirection(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 folded = n.xy;
    if (n.z < 0.0) {
        folded = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    }
    return folded;
}

vec3 directionFromOctahedral(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) {
        n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    }
    return normalize(n);
}

// W(q) = c + |q - c| * F(dir(q - c)) with F's texel for that direction already at hand.
vec3 warpPointWith(vec3 qMm, vec4 texel) {
    vec3 c = u.mapCentreMm;
    float radius = length(qMm - c);
    if (radius < 1e-6) return c;  // the centre maps to itself; its direction is undefined
    return c + radius * (caveToVolume() * normalize(texel.xyz));
}

// W(q) = c + |q - c| * F(dir(q - c)): the warp of space about the map centre c.
vec3 warpPoint(vec3 qMm) { return warpPointWith(qMm, cubeTexelAt(qMm)); }

#endif
