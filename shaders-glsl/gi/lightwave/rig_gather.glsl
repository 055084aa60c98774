// The thesis's indirect term (eq 4.5 without its specular part; cpu.rs `gather` is the f64
// definition): the mean over `count` VPLs from `first` of weight x sat(n·ω) x lobe, with the
// 240° lobe (cos θ + 0.5)/1.5 and no distance falloff. The includer declares `vpls`, a texel
// buffer of two texels per VPL: (position, weight), (direction, light index). Texels, not a
// storage buffer: lavapipe reads a storage buffer lane by lane with a branch per word wherever
// the index is not made of constants (a loop counter here), and a texel fetch for all the lanes
// at once; a GPU reads either through its caches (docs/lightwave.md, "The VPLs read as
// texels").

float lobe(float cos_theta) {
    return clamp((cos_theta + 0.5) / 1.5, 0.0, 1.0);
}

// The sum (not yet divided by `count`) over every `stride`-th VPL from `first + start`.
float rig_gather_part(uint first, uint count, uint start, uint stride, vec3 p, vec3 n) {
    float sum = 0.0;
    for (uint j = first + start; j < first + count; j += stride) {
        vec4 position_weight = texelFetch(vpls, int(2u * j));
        vec3 direction = texelFetch(vpls, int(2u * j + 1u)).xyz;
        vec3 d = position_weight.xyz - p;
        float length_sq = dot(d, d);
        if (length_sq <= 1e-24) continue;
        vec3 omega = d * inversesqrt(length_sq);
        sum += position_weight.w * clamp(dot(n, omega), 0.0, 1.0) * lobe(-dot(direction, omega));
    }
    return sum;
}

float rig_gather(uint first, uint count, vec3 p, vec3 n) {
    return rig_gather_part(first, count, 0u, 1u, p, n) / float(count);
}
