#version 450
// Test kernel with a known result: out[i] = in[i] * 3 + i, for every i < count.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Input { uint values[]; } inputBuffer;
layout(std430, binding = 1) writeonly buffer Output { uint values[]; } outputBuffer;
layout(push_constant) uniform Push { uint count; } push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    outputBuffer.values[i] = inputBuffer.values[i] * 3u + i;
}
