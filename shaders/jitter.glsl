// Deterministic per-pixel jitter of ray starts: a hash of pixel and frame seed, so the same
// seed renders the same image and neighbouring pixels decorrelate (no wood-grain banding).
#ifndef JITTER_GLSL
#define JITTER_GLSL

// pcg3d (Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 2020).
uvec3 pcg3d(uvec3 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    return v;
}

// Uniform in [0, 1): 24 random bits.
float jitterFraction(uvec2 pixel, uint seed) {
    return float(pcg3d(uvec3(pixel, seed)).x >> 8u) * (1.0 / 16777216.0);
}

#endif
