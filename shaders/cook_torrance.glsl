// Cook-Torrance shading (GGX distribution, Smith-Schlick geometry, Schlick Fresnel) lit by a
// headlight at the eye whose intensity falls off with distance, the cue that tells near folds
// from far ones in a colon. Two-sided: the side facing the eye is lit.
#ifndef COOK_TORRANCE_GLSL
#define COOK_TORRANCE_GLSL

const float kPi = 3.14159265358979;

vec3 shadeCookTorrance(vec3 normal, vec3 toEye, float distanceMm, vec3 baseColor) {
    float roughness = u.roughness;
    float f0 = u.fresnelF0;
    float ambient = u.ambient;
    // Light and eye coincide: L = V = H, so N.L = N.V = N.H and V.H = 1.
    float nDotV = clamp(abs(dot(normal, toEye)), 1e-4, 1.0);
    float alpha = roughness * roughness;
    float alpha2 = alpha * alpha;
    float denom = nDotV * nDotV * (alpha2 - 1.0) + 1.0;
    float distribution = alpha2 / (kPi * denom * denom);
    float k = (roughness + 1.0) * (roughness + 1.0) / 8.0;
    float geometry1 = nDotV / (nDotV * (1.0 - k) + k);
    float geometry = geometry1 * geometry1;
    float fresnel = f0;
    float specular = distribution * geometry * fresnel / (4.0 * nDotV * nDotV);
    vec3 diffuse = (1.0 - fresnel) * baseColor / kPi;
    float radiance = kPi / (1.0 + u.lightFalloffPerMm2 * distanceMm * distanceMm);
    return ambient * baseColor + (diffuse + vec3(specular)) * radiance * nDotV;
}

#endif
