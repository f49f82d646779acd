#version 450
// Benchmark kernel: the ceiling of plain trilinear sampling on this device. Each thread takes
// `stepsPerRay` samples of the volume along a straight line, as a ray caster's inner loop
// would with nothing else to do, and writes their sum so no sample can be optimised away.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler3D volumeTexture;
layout(std430, binding = 1) writeonly buffer Sums { float sums[]; };
layout(push_constant) uniform Push {
    uvec2 imageSize;
    uint stepsPerRay;
    float stepTex;  // step length in texture coordinates
} push;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= push.imageSize.x || pixel.y >= push.imageSize.y) return;
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(push.imageSize) * 2.0 - 1.0;
    vec3 dir = normalize(vec3(ndc * 0.7, 1.0));  // a 70-degree pinhole looking along +z
    vec3 tc = vec3(0.5, 0.5, 0.1);
    vec3 stepVector = dir * push.stepTex;
    float sum = 0.0;
    for (uint i = 0u; i < push.stepsPerRay; ++i) {
        sum += textureLod(volumeTexture, tc, 0.0).r;
        tc += stepVector;
    }
    sums[pixel.y * push.imageSize.x + pixel.x] = sum;
}
