#version 460
// Irradiance splatting (spec 003 Alg. 3-4): a record's weight at the pixel's surface point and
// its gradient-extrapolated irradiance, added (blended one + one) as (w E', w). The albedo is
// applied when the sums are normalised (normalise.comp), so the buffer holds irradiance.
#include "gi/irradiance_cache/ic.glsl"

layout(binding = IC_GBUFFER_POSITION, rgba32f) readonly uniform image2D gbuffer_position;
layout(binding = IC_GBUFFER_NORMAL, rgba16f) readonly uniform image2D gbuffer_normal;

layout(push_constant) uniform Push {
    mat4 view_projection;
    uvec2 size;
    uint round_only;
    float accuracy;
    float smooth_weight;
    float normal_factor;
    uint generation;
} pc;

// The quad's record (splat.vert).
layout(location = 0) flat in vec4 in_record[RECORD_WORDS];
layout(location = 0) out vec4 out_splat;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = imageLoad(gbuffer_position, pixel);
    if (position.w == 0.0) discard;
    vec3 n = normalize(imageLoad(gbuffer_normal, pixel).xyz);
    Record record = record_from_words(in_record);
    Weighting weighting = Weighting(pc.accuracy, pc.smooth_weight, pc.normal_factor);
    float w = record_weight(record, weighting, position.xyz, n);
    if (w <= 0.0) discard;
    out_splat = vec4(w * record_extrapolate(record, position.xyz, n), w);
}
