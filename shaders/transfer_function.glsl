// The 1D transfer function: HU -> colour and opacity, with opacity given per reference step
// and corrected for the actual step length so images do not depend on the sampling rate. For a
// fixed step the host has corrected the table already; the adaptive step corrects per sample.
#ifndef TRANSFER_FUNCTION_GLSL
#define TRANSFER_FUNCTION_GLSL

// Whether a sample of this value may be visible: outside the range the table's opacity is zero,
// and the march skips the table's fetch (engine::visibleHuRangeOf).
bool isPossiblyVisible(float hu) { return hu > u.transferVisibleFromHu && hu < u.transferVisibleToHu; }

vec4 classify(float hu, float stepMm) {
    float x = (hu - u.transferFirstHu) * u.transferIndexPerHu + u.transferHalfEntry;  // entry e at texel centre (e + .5) / n
    vec4 c = textureLod(transferFunction, vec2(x, 0.5), 0.0);
    if (kAdaptive) c.a = 1.0 - pow(max(1.0 - c.a, 0.0), stepMm / u.transferReferenceStepMm);
    return c;
}

#endif
