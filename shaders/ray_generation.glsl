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

// W(q) = c + |q - c| * F(dir(q - c)): the warp of space about the map centre c. The cube map
// holds F in CAVE axes (its texels' xyz not normalised), so the direction is turned into the
// CAVE frame for the lookup and the answer back.
vec3 warpPoint(vec3 qMm) {
    vec3 c = u.mapCentreMm;
    vec3 offset = qMm - c;
    float radius = length(offset);
    if (radius < 1e-6) return c;  // the centre maps to itself; its direction is undefined
    mat3 toVolume = caveToVolume();
    vec4 texel = textureLod(cubeMap, transpose(toVolume) * (offset / radius), 0.0);
    return c + radius * (toVolume * normalize(texel.xyz));
}

#endif
