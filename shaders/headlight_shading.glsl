// Blinn-Phong shading lit by a headlight at the eye; the surface is lit from whichever side
// faces the eye, so the inside of a lumen is shaded like the outside of an object.
#ifndef HEADLIGHT_SHADING_GLSL
#define HEADLIGHT_SHADING_GLSL

vec3 shadeHeadlight(vec3 normal, vec3 toEye, vec3 baseColor) {
    float nDotL = abs(dot(normal, toEye));  // light and eye coincide: L = H = V
    float ambient = 0.15;
    float diffuse = 0.75 * nDotL;
    float specular = 0.25 * pow(nDotL, 40.0);
    return baseColor * (ambient + diffuse) + vec3(specular);
}

#endif
