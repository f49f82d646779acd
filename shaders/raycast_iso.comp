#version 450
// Iso-surface ray caster: one thread per pixel; each ray marches through the volume's box
// from the eye, stops at the first sample at or above the iso value, refines the crossing by
// bisection, and shades it with a headlight. Writes the colour and the hit position.
#extension GL_GOOGLE_include_directive : require

#include "host_device.h"

layout(local_size_x = CVC_TILE_SIZE, local_size_y = CVC_TILE_SIZE) in;

layout(std140, binding = CVC_BINDING_UNIFORMS) uniform Uniforms { RaycastUniforms u; };
layout(binding = CVC_BINDING_VOLUME) uniform sampler3D volumeTexture;
layout(binding = CVC_BINDING_COLOR_IMAGE, rgba8) uniform writeonly image2D colorImage;
layout(binding = CVC_BINDING_HIT_IMAGE, rgba32f) uniform writeonly image2D hitImage;

#include "ray_box.glsl"
#include "volume_sampling.glsl"
#include "headlight_shading.glsl"

const vec3 kSurfaceColor = vec3(0.93, 0.62, 0.52);
const vec3 kBackground = vec3(0.04, 0.05, 0.07);

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= u.imageSize.x || pixel.y >= u.imageSize.y) return;

    // Pixel centre in [-1, 1]^2, y up (row 0 is the top of the image).
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(u.imageSize.xy) * 2.0 - 1.0;
    ndc.y = -ndc.y;
    vec3 eye = u.eyeMm.xyz;
    vec3 dir = normalize(u.forward.xyz + ndc.x * u.rightScaled.xyz + ndc.y * u.upScaled.xyz);

    vec2 span = intersectBox(eye, dir, u.boxMinMm.xyz, u.boxMaxMm.xyz);
    float tStart = max(span.x, 0.0);
    float tEnd = span.y;

    float stepMm = u.march.x;
    float iso = u.march.y;
    int bisectionSteps = int(u.march.z);
    int maxSteps = int(u.march.w);

    vec3 color = kBackground;
    vec4 hit = vec4(0.0);
    if (tStart < tEnd) {
        float tPrev = tStart;
        float valuePrev = sampleHu(eye + tStart * dir);
        bool isHit = valuePrev >= iso;  // the ray starts inside matter: hit where it enters
        float tHit = tStart;
        int steps = min(maxSteps, int(ceil((tEnd - tStart) / stepMm)));
        for (int i = 1; i <= steps && !isHit; ++i) {
            float t = min(tStart + float(i) * stepMm, tEnd);
            float value = sampleHu(eye + t * dir);
            if (value >= iso) {
                // The crossing lies in (tPrev, t]: bisect, keeping lo below and hi at or above.
                float lo = tPrev, hi = t;
                for (int b = 0; b < bisectionSteps; ++b) {
                    float mid = 0.5 * (lo + hi);
                    if (sampleHu(eye + mid * dir) >= iso) hi = mid; else lo = mid;
                }
                // Final linear interpolation between the bracketing samples.
                float vLo = sampleHu(eye + lo * dir);
                float vHi = sampleHu(eye + hi * dir);
                float f = (vHi > vLo) ? clamp((iso - vLo) / (vHi - vLo), 0.0, 1.0) : 1.0;
                tHit = mix(lo, hi, f);
                isHit = true;
            }
            tPrev = t;
        }
        if (isHit) {
            vec3 pHit = eye + tHit * dir;
            vec3 g = gradientHu(pHit);
            float gLength = length(g);
            vec3 normal = gLength > 1e-6 ? -g / gLength : -dir;
            color = shadeHeadlight(normal, -dir, kSurfaceColor);
            hit = vec4(pHit, 1.0);
        }
    }
    // Gamma 2.2 for display.
    imageStore(colorImage, ivec2(pixel), vec4(pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0));
    imageStore(hitImage, ivec2(pixel), hit);
}
