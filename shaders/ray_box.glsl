// Ray / axis-aligned box intersection (slab method) that never divides by a zero component.
#ifndef RAY_BOX_GLSL
#define RAY_BOX_GLSL

// A direction component of exactly zero would give 0/0 = NaN in the slab test when the
// origin lies on a slab plane; a tiny signed stand-in gives +-infinity-like slabs instead.
vec3 safeInverse(vec3 dir) {
    const float tiny = 1e-20;
    vec3 safe = vec3(abs(dir.x) < tiny ? (dir.x < 0.0 ? -tiny : tiny) : dir.x,
                     abs(dir.y) < tiny ? (dir.y < 0.0 ? -tiny : tiny) : dir.y,
                     abs(dir.z) < tiny ? (dir.z < 0.0 ? -tiny : tiny) : dir.z);
    return 1.0 / safe;
}

// Returns (tEnter, tExit) of origin + t * dir through [boxMin, boxMax]; tEnter > tExit: miss.
vec2 intersectBox(vec3 origin, vec3 dir, vec3 boxMin, vec3 boxMax) {
    vec3 invDir = safeInverse(dir);
    vec3 t0 = (boxMin - origin) * invDir;
    vec3 t1 = (boxMax - origin) * invDir;
    vec3 tNear = min(t0, t1);
    vec3 tFar = max(t0, t1);
    return vec2(max(max(tNear.x, tNear.y), tNear.z), min(min(tFar.x, tFar.y), tFar.z));
}

#endif
