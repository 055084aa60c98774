//! The path tracer's counter-based random numbers, bit-identical to shaders-glsl/common/rng.glsl.

/// PCG-RXS-M-XS hash (Jarzynski & Olano 2020).
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// A uniform float in [0, 1) for (seed, pixel, sample, dimension).
pub fn random_float(seed: u32, pixel: u32, sample: u32, dimension: u32) -> f32 {
    let h = pcg_hash(seed ^ pcg_hash(pixel ^ pcg_hash(sample ^ pcg_hash(dimension))));
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_enough_and_in_range() {
        let n = 100_000;
        let mut sum = 0.0f64;
        let mut buckets = [0u32; 10];
        for i in 0..n {
            let x = random_float(1, i, 3, 7);
            assert!((0.0..1.0).contains(&x));
            sum += f64::from(x);
            buckets[(x * 10.0) as usize] += 1;
        }
        assert!((sum / f64::from(n) - 0.5).abs() < 0.005);
        assert!(
            buckets.iter().all(|&b| (9_500..10_500).contains(&b)),
            "{buckets:?}"
        );
    }

    #[test]
    fn dimensions_and_seeds_decorrelate() {
        assert_ne!(random_float(1, 2, 3, 4), random_float(1, 2, 3, 5));
        assert_ne!(random_float(1, 2, 3, 4), random_float(2, 2, 3, 4));
        assert_eq!(pcg_hash(0), pcg_hash(0));
    }
}
