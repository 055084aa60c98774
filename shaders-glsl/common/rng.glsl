#ifndef VKGI_RNG_GLSL
#define VKGI_RNG_GLSL
// Counter-based random numbers: every number is a hash of (seed, pixel, sample, dimension), so
// a sample's path does not depend on earlier samples and the CPU mirror (src/reference/rng.rs)
// reproduces it exactly.

// PCG-RXS-M-XS hash (Jarzynski & Olano 2020).
uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A uniform float in [0, 1) with 24 random bits.
float random_float(uint seed, uint pixel, uint sample_index, uint dimension) {
    uint h = pcg_hash(seed ^ pcg_hash(pixel ^ pcg_hash(sample_index ^ pcg_hash(dimension))));
    return float(h >> 8u) * (1.0 / 16777216.0);
}

#endif
