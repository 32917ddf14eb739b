// The surface every scene pass shades (set 1, `render::materials`): base colour = factor x
// texture (sRGB-decoded by its format) x COLOR_0, cut out below the MASK cutoff, plus
// emissive; unlit materials skip the lighting. The alpha a pass writes stays the technique's:
// the material's alpha only cuts out (MASK) and blends (BLEND).
layout(set = 1, binding = 0) uniform MaterialUniforms {
    vec4 base_colour;
    vec4 emissive;
    // Rows of the 2x3 UV transforms (KHR_texture_transform).
    vec4 base_uv[2];
    vec4 emissive_uv[2];
    // x: alpha cutoff (< 0: none), y: unlit, z: UV set of the base texture, w: of the emissive.
    vec4 params;
} material;
layout(set = 1, binding = 1) uniform sampler2D base_colour_texture;
layout(set = 1, binding = 2) uniform sampler2D emissive_texture;

vec2 material_uv(vec4 rows[2], float set, vec2 uv0, vec2 uv1) {
    vec3 uv = vec3(set > 0.5 ? uv1 : uv0, 1.0);
    return vec2(dot(rows[0].xyz, uv), dot(rows[1].xyz, uv));
}

// Base colour (linear RGBA) at this fragment.
vec4 material_base(vec2 uv0, vec2 uv1, vec4 vertex_colour) {
    vec2 uv = material_uv(material.base_uv, material.params.z, uv0, uv1);
    return material.base_colour * texture(base_colour_texture, uv) * vertex_colour;
}

vec3 material_emissive(vec2 uv0, vec2 uv1) {
    vec2 uv = material_uv(material.emissive_uv, material.params.w, uv0, uv1);
    return material.emissive.rgb * texture(emissive_texture, uv).rgb;
}

// Whether a MASK material cuts this base colour out.
bool material_cut(vec4 base) {
    return base.a < material.params.x;
}

// The base colour of a fragment that stays: in the `_masked` variants (ALPHA_MASK defined), a
// cut-out fragment is discarded here. Opaque variants compile no discard, which keeps early
// depth testing on a tiler.
vec4 material_surface(vec2 uv0, vec2 uv1, vec4 vertex_colour) {
    vec4 base = material_base(uv0, uv1, vertex_colour);
#ifdef ALPHA_MASK
    if (material_cut(base)) {
        discard;
    }
#endif
    return base;
}

// The shaded colour: `light` is the lighting factor of the pass (ambient + diffuse, shadowed
// or toon), which an unlit material ignores; emissive is added.
vec3 material_shade(vec4 base, vec3 light, vec2 uv0, vec2 uv1) {
    vec3 lit = material.params.y > 0.5 ? base.rgb : base.rgb * light;
    return lit + material_emissive(uv0, uv1);
}

// The shading normal: flipped on back faces, which only double-sided materials draw.
vec3 surface_normal(vec3 interpolated) {
    vec3 n = normalize(interpolated);
    return gl_FrontFacing ? n : -n;
}

// The alpha a scene pass writes: the technique's (counter start, outline mask, receiver
// factor) for opaque and masked materials; for a blended one, its own alpha, which the blend
// equation uses as the colour factor and never stores (alpha blend ZERO, ONE).
#ifdef ALPHA_BLEND
#define written_alpha(base) (base).a
#else
#define written_alpha(base) object.colour.a
#endif
