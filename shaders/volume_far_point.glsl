// The far end of a volume from its push constants (volume_push.glsl), computed as the CPU
// computes it (`precise`: no fused multiply-add), so that both agree to the bit.

// Where `p` goes at the volume's far end (mesh::shadow_volume::far_point and start_volume).
vec4 far_point(vec3 p) {
    uint far_end = (object.flags >> 1) & 3u;
    if (far_end == 1u) {
        precise vec3 along = p + object.reach * object.light.xyz;
        return vec4(along, 1.0);
    }
    if (far_end == 2u) {
        precise vec3 scaled = object.light.xyz + object.reach * (p - object.light.xyz);
        return vec4(scaled, 1.0);
    }
    if (object.light.w == 0.0) {
        return vec4(object.light.xyz, 0.0);
    }
    precise vec3 away = p - object.light.xyz;
    return vec4(away, 0.0);
}
