#ifndef VKGI_IC_GLSL
#define VKGI_IC_GLSL
// Irradiance-cache records and Ward's weight (spec 003 §2-§4); the f64 twin is
// src/gi/irradiance_cache/cpu.rs, the Rust layout src/gi/irradiance_cache/records.rs.
#include "common/math.glsl"

struct Record {
    vec4 position_harmonic;  // xyz p_k, w R_k (0 until the record's hemisphere is reduced)
    vec4 normal_footprint;   // xyz n_k, w world size of a view pixel at p_k when it was placed
    vec4 irradiance;         // rgb E_k (W/m²)
    vec4 rotation[3];        // per channel, xyz: ∇_r E
    vec4 translation[3];     // per channel, xyz: ∇_t E
};

// A record as its nine words, and back (the splat hands a record to its fragments so).
const int RECORD_WORDS = 9;

vec4[RECORD_WORDS] record_words(Record r) {
    return vec4[RECORD_WORDS](r.position_harmonic, r.normal_footprint, r.irradiance,
                              r.rotation[0], r.rotation[1], r.rotation[2],
                              r.translation[0], r.translation[1], r.translation[2]);
}

Record record_from_words(vec4 w[RECORD_WORDS]) {
    return Record(w[0], w[1], w[2], vec4[3](w[3], w[4], w[5]), vec4[3](w[6], w[7], w[8]));
}

// The cache's counters (Rust: records::CacheState).
struct CacheState {
    uint count;       // records in the cache
    uint first;       // the records this round added: [first, end)
    uint end;
    uint holes;       // pixels found uncovered (one per tile) in the last round
    uint overflowed;  // candidates refused because the cache was full, since it was emptied
    uint placed;      // records added since the cache was emptied
    uint added;       // records the last placement round added
    uint generation;  // the cache holds records of this generation; another means it is empty
    uint bounce;      // records [0, refreshed) hold this many bounces, the rest one fewer
    uint refreshed;   // records recomputed for `bounce` so far
    uint previous_count;  // records in the previous bounce's snapshot
    uint snapshot;    // 1: this round copies the cache into the snapshot
    uint done;        // 1: the cache holds every bounce asked for (until it is emptied)
    float change;     // relative change of Σ E over the records from the previous bounce
};

// An empty cache of `generation`, holding one bounce.
void empty_cache(inout CacheState s, uint generation) {
    s.count = 0u;
    s.first = 0u;
    s.end = 0u;
    s.overflowed = 0u;
    s.placed = 0u;
    s.added = 0u;
    s.generation = generation;
    s.bounce = 1u;
    s.refreshed = 0u;
    s.previous_count = 0u;
    s.snapshot = 0u;
    s.done = 0u;
    s.change = 0.0;
}

// How records weigh points (Rust: cpu::Weighting).
struct Weighting {
    float accuracy;       // Ward's a
    float smooth_weight;  // 1: w - 1/a (§8.2), 0: w
    float normal_factor;  // kappa in sqrt(kappa (1 - n.n_k))
};

// Record k's weight at p with normal n; 0 where it does not contribute (cpu::Weighting::weight).
float record_weight(Record k, Weighting w, vec3 p, vec3 n) {
    float a = w.accuracy;
    float harmonic = k.position_harmonic.w;
    if (harmonic <= 0.0) return 0.0;
    vec3 diff = p - k.position_harmonic.xyz;
    float e1 = dot(diff, diff) / (harmonic * harmonic);
    // 1 - n.n_k as |n - n_k|² / 2 (unit vectors): no cancellation where the normals agree.
    vec3 turn = n - k.normal_footprint.xyz;
    float e2 = w.normal_factor * 0.5 * dot(turn, turn);
    if (e1 + e2 > a * a) return 0.0;
    float inverse = max(IC_MIN_INVERSE_WEIGHT, sqrt(e1) + sqrt(e2));
    if (inverse > a) return 0.0;
    if (dot(diff, n + k.normal_footprint.xyz) < -2.0 * IC_BEHIND_TOLERANCE * harmonic) return 0.0;
    float weight = 1.0 / inverse - w.smooth_weight / a;
    return min(max(weight, 0.0), IC_MAX_WEIGHT);
}

// Record k's irradiance extrapolated to p, n by its gradients, never negative (cpu::extrapolate).
vec3 record_extrapolate(Record k, vec3 p, vec3 n) {
    vec3 turn = cross(k.normal_footprint.xyz, n);
    vec3 shift = p - k.position_harmonic.xyz;
    vec3 e = k.irradiance.rgb;
    for (int c = 0; c < 3; ++c) {
        e[c] += dot(turn, k.rotation[c].xyz) + dot(shift, k.translation[c].xyz);
    }
    return max(e, vec3(0.0));
}

#endif
