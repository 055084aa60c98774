#version 460
// Irradiance splatting (spec 003 §3, Alg. 2): one screen-space quad per record, six vertices
// each, covering the projection of the record's sphere of influence (centre p_k, radius a·R_k)
// conservatively: the projected corners of the sphere's bounding box, or the whole screen when
// the box reaches behind the eye (cpu::splat_bounds). Every record, or only this round's.
#include "gi/irradiance_cache/ic.glsl"

layout(binding = IC_RECORDS, std430) readonly buffer Records { Record records[]; };
layout(binding = IC_STATE, std430) readonly buffer State { CacheState state; };

layout(push_constant) uniform Push {
    mat4 view_projection;
    uvec2 size;
    uint round_only;   // 1: this round's records, 0: all
    float accuracy;
    float smooth_weight;
    float normal_factor;
    uint generation;   // records of another generation are gone
} pc;

// The record, word by word (position, normal, irradiance, rotation and translation gradients),
// handed to every fragment of its quad: a fragment reading it from the buffer read it lane by
// lane on lavapipe.
layout(location = 0) flat out vec4 out_record[RECORD_WORDS];

const vec2 CORNERS[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
    uint index = (pc.round_only == 1u ? state.first : 0u) + gl_VertexIndex / 6;
    uint end = pc.round_only == 1u ? state.end : state.count;
    if (state.generation != pc.generation) end = 0u;
    if (index >= end) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    Record record = records[index];
    out_record = record_words(record);
    vec3 centre = record.position_harmonic.xyz;
    float radius = pc.accuracy * record.position_harmonic.w;
    vec2 lo = vec2(1e30);
    vec2 hi = vec2(-1e30);
    bool full = false;
    for (int corner = 0; corner < 8; ++corner) {
        vec3 sign = vec3((corner & 1) != 0 ? 1.0 : -1.0, (corner & 2) != 0 ? 1.0 : -1.0,
                         (corner & 4) != 0 ? 1.0 : -1.0);
        vec4 clip = pc.view_projection * vec4(centre + sign * radius, 1.0);
        if (clip.w <= IC_MIN_CLIP_W) {
            full = true;
            break;
        }
        lo = min(lo, clip.xy / clip.w);
        hi = max(hi, clip.xy / clip.w);
    }
    if (full) {
        lo = vec2(-1.0);
        hi = vec2(1.0);
    }
    // Clamped to just outside the screen (the quad then holds every covered pixel centre).
    lo = clamp(lo, vec2(-1.01), vec2(1.01));
    hi = clamp(hi, vec2(-1.01), vec2(1.01));
    gl_Position = vec4(mix(lo, hi, CORNERS[gl_VertexIndex % 6]), 0.0, 1.0);
}
