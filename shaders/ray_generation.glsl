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

// W(q) = c + |q - c| * F(dir(q - c)): the warp of space about the map centre c.
vec3 warpPoint(vec3 qMm) {
    vec3 c = u.mapCentreMm;
    vec3 offset = qMm - c;
    float radius = length(offset);
    if (radius < 1e-6) return c;  // the centre maps to itself; its direction is undefined
    return c + radius * sceneFromDisplay(offset / radius).xyz;
}

#endif
