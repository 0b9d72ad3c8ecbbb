/* gbuffer_textured.c - the G-buffer program for materials with texture maps, and the scene's
 * textures (each image file decoded once, with its mips).
 *
 * GLSL twin: shaders/gbuffer_textured.vert, shaders/gbuffer_textured.frag, with the same names
 * (uKdMap .. uMaskMap, uKdMapST .. uMaskMapST, uMaps, uAlphaCutoff; varyings vWorldPos, vNormal,
 * vTexCoord, vTangent). Untextured materials keep the built-in pair (gbuffer_shader.c), which pays
 * nothing for this program: no quads, no derivatives, no UV or tangent varyings.
 *
 * What a map does (docs/scene-format.md "Texture maps"): kd = uKd * kd_map.rgb, ks = uKs *
 * ks_map.rgb, alpha = uAlpha * alpha_map.r (a GGX material: the lobe parameter of roughness
 * uRoughness * alpha_map.r, gbuffer.h), the normal perturbed by normal_map in tangent space
 * as glTF does it (B = cross(N, T) * w, N' = normalize(T n.x + B n.y + N n.z), n = rgb * 2 - 1),
 * discard where mask_map.r (else kd_map.a) < uAlphaCutoff. Each map reads its own transformed
 * coordinate vTexCoord * ST.xy + ST.zw with an implicit level of detail, as GLSL's texture().
 * glTF's metallic-roughness per texel (uMetallic >= 0) and the extra channels (occlusion,
 * emission) are separate functions after the texel is written, so the common path is unchanged. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gbuffer_textured.h"
#include "texture.h"

/* uMaps' public bits (softlight/gbuffer_program.h) are the map slots' (scene.h). */
_Static_assert(SL_GBUFFER_MAP_KD == 1 << SL_MAP_KD && SL_GBUFFER_MAP_KS == 1 << SL_MAP_KS &&
                   SL_GBUFFER_MAP_ALPHA == 1 << SL_MAP_ALPHA && SL_GBUFFER_MAP_NORMAL == 1 << SL_MAP_NORMAL &&
                   SL_GBUFFER_MAP_MASK == 1 << SL_MAP_MASK &&
                   SL_GBUFFER_MAP_METALLIC_ROUGHNESS == 1 << SL_MAP_METALLIC_ROUGHNESS &&
                   SL_GBUFFER_MAP_OCCLUSION == 1 << SL_MAP_OCCLUSION &&
                   SL_GBUFFER_MAP_EMISSIVE == 1 << SL_MAP_EMISSIVE && SL_GBUFFER_MAP_CUTOFF == 1 << SL_MAP_COUNT,
               "SL_GBUFFER_MAP_* are 1 << sl_map_slot");
_Static_assert(SL_GBUFFER_VARYING_COUNT == SL_GBUFFER_TEX_VARYINGS, "the public varyings are the program's");

/* gbuffer_textured.vert: main(). The tangent is a direction on the surface: it goes through
 * mat3(uModel), not the normal matrix; its handedness w passes through (scene transforms have no
 * mirroring: negative scales are refused by the scene reader). */
void sl_gbuffer_tex_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    const sl_gbuffer_tex_uniforms *u = uniforms;
    vec4 world = mat4_mul_vec4(u->uModel, vec4_from3(in->position, 1.0f));
    vec3 vWorldPos = xyz(world);
    vec3 vNormal = mat3_mul_vec3(u->uNormalMatrix, in->normal);
    vec2 vTexCoord = in->texcoord;
    vec3 t = mat3_mul_vec3(u->uModel3, vec3(in->tangent.x, in->tangent.y, in->tangent.z));
    *clip = mat4_mul_vec4(u->uViewProj, world);
    float out[SL_GBUFFER_TEX_VARYINGS] = {vWorldPos.x, vWorldPos.y, vWorldPos.z, vNormal.x, vNormal.y,
                                          vNormal.z,   vTexCoord.x, vTexCoord.y, t.x,       t.y,
                                          t.z,         in->tangent.w};
    memcpy(varyings, out, sizeof out);
}

/* GLSL's texture(s, uv): glsl.h's texture(), operation for operation (one lambda per
 * quad from the coarse differences of uv, one derivative record), with the trace hook between its
 * steps, where the derivatives and the level are at hand. */
static vec4 texture_traced(const sl_fragment_in *in, const sl_sampler2D *s, vec2 uv, int slot,
                           const sl_gbuffer_tex_uniforms *u)
{
    if (!u->trace)
        return texture(in, s, uv);
    float v[2] = {uv.x, uv.y}, dx[2], dy[2];
    sl_quad_gradients(in, true, v, 2, dx, dy);
    vec2 dPdx = vec2(dx[0], dx[1]), dPdy = vec2(dy[0], dy[1]);
    float lambda = sl_texture_lambda_quad(s, dPdx, dPdy, 0.0f);
    vec4 value = sl_texture_sample(s, uv, lambda);
    u->trace(u->trace_ctx, in, slot, s, uv, dPdx, dPdy, lambda, value);
    return value;
}

static vec2 map_uv(vec2 uv, vec4 st) { return vec2(uv.x * st.x + st.z, uv.y * st.y + st.w); }

/* What a fragment read from each map slot (sl_map_slot), GL's defaults where none is bound. */
typedef struct {
    vec4 map[SL_MAP_COUNT];
} map_values;

static void maps_unbound(map_values *m)
{
    for (int slot = 0; slot < SL_MAP_COUNT; slot++)
        m->map[slot] = vec4(1, 1, 1, 1);
    m->map[SL_MAP_NORMAL] = vec4(0.5f, 0.5f, 1, 1);
}

/* gbuffer_textured.frag: metallic_roughness. glTF's metallic-roughness per texel: the texel's kd so
 * far is the base colour (uKd * kd_map.rgb); m = uMetallic * mr.b, kd = base (1 - m),
 * ks = 0.04 + (base - 0.04) m (mix(0.04, base, m)), roughness times mr.g. */
static void metallic_roughness(const sl_gbuffer_tex_uniforms *u, const map_values *m, sl_gbuffer_texel *g)
{
    vec4 mr = m->map[SL_MAP_METALLIC_ROUGHNESS], gloss = m->map[SL_MAP_ALPHA];
    vec3 base = g->kd;
    float metal = u->uMetallic * mr.z;
    g->kd = scale3(base, 1.0f - metal);
    g->ks = vec3(0.04f + (base.x - 0.04f) * metal, 0.04f + (base.y - 0.04f) * metal, 0.04f + (base.z - 0.04f) * metal);
    g->alpha = sl_gbuffer_ggx_alpha(u->uRoughness * gloss.x * mr.y);
}

/* gbuffer_textured.frag: oExtra. The fragment's extra texel, tagged with its depth (gbuffer.h),
 * where its stores take effect (sl_fragment_stores: not a helper's, as it writes no texel). */
static void write_extra(const sl_gbuffer_tex_uniforms *u, int x, int y, bool store, float depth, const map_values *m)
{
    if (!store)
        return;
    vec4 occ = m->map[SL_MAP_OCCLUSION], em = m->map[SL_MAP_EMISSIVE];
    sl_gbuffer_extra *e = u->extra + (size_t)y * (size_t)u->extra_width + (size_t)x;
    e->occlusion = 1.0f + u->uOcclusionStrength * (occ.x - 1.0f);
    e->emissive = mul3(u->uEmissive, vec3(em.x, em.y, em.z));
    e->depth = depth;
}

/* gbuffer_textured.frag: the normal, perturbed by the normal map's texel nt when one is bound. The
 * reference form's; shading_normals4 below is the same for a quad's four lanes. */
static vec3 shading_normal(const sl_gbuffer_tex_uniforms *u, const float *v, vec4 nt)
{
    vec3 vNormal = vec3(v[3], v[4], v[5]);
    vec4 vTangent = vec4(v[8], v[9], v[10], v[11]);
    vec3 n = dot(vNormal, vNormal) > 1e-30f ? normalize(vNormal) : vec3(0, 0, 1);
    vec3 t = vec3(vTangent.x, vTangent.y, vTangent.z);
    if ((u->uMaps & SL_GBUFFER_MAP_NORMAL) && dot(t, t) > 1e-30f) {
        t = normalize(t);
        vec3 b = scale3(cross(n, t), vTangent.w);
        vec3 mt = vec3(nt.x * 2.0f - 1.0f, nt.y * 2.0f - 1.0f, nt.z * 2.0f - 1.0f);
        vec3 p = add3(add3(scale3(t, mt.x), scale3(b, mt.y)), scale3(n, mt.z));
        n = dot(p, p) > 1e-30f ? normalize(p) : n;
    }
    return n;
}

/* shading_normal for `lanes` lanes, in vector loops over them: each lane's value is
 * shading_normal's, operation for operation (dot as ((x x + y y) + z z), normalize as a product
 * with 1 / sqrt, cross and the sums in its order), with selects for its branches, so the bits
 * are the same (tests/cli/textured_quad_form.sh); the three square roots and divisions of a lane
 * then cost what one costs for a vector of lanes. v[i][j]: varying i of lane j; mx, my, mz: the
 * normal map's texel (read only when one is bound). */
static void shading_normals(const sl_gbuffer_tex_uniforms *u, int lanes, const float *const v[SL_GBUFFER_TEX_VARYINGS],
                            const float *mx, const float *my, const float *mz, float *nx, float *ny, float *nz)
{
    const float *vx = v[3], *vy = v[4], *vz = v[5];
#pragma omp simd
    for (int l = 0; l < lanes; l++) {
        sl_gbuffer_normal_lane(vx[l], vy[l], vz[l], &nx[l], &ny[l], &nz[l]);
    }
    if (!(u->uMaps & SL_GBUFFER_MAP_NORMAL))
        return;
    const float *tx = v[8], *ty = v[9], *tz = v[10], *tw = v[11];
#pragma omp simd
    for (int l = 0; l < lanes; l++) {
        float td = tx[l] * tx[l] + ty[l] * ty[l] + tz[l] * tz[l];
        bool tok = td > 1e-30f;
        float tinv = 1.0f / sqrtf(tok ? td : 1.0f);
        float ux = tx[l] * tinv, uy = ty[l] * tinv, uz = tz[l] * tinv;
        float bx = (ny[l] * uz - nz[l] * uy) * tw[l];
        float by = (nz[l] * ux - nx[l] * uz) * tw[l];
        float bz = (nx[l] * uy - ny[l] * ux) * tw[l];
        float ax = mx[l] * 2.0f - 1.0f, ay = my[l] * 2.0f - 1.0f, az = mz[l] * 2.0f - 1.0f;
        float px = ux * ax + bx * ay + nx[l] * az;
        float py = uy * ax + by * ay + ny[l] * az;
        float pz = uz * ax + bz * ay + nz[l] * az;
        float pd = px * px + py * py + pz * pz;
        bool pok = tok && pd > 1e-30f;
        float pinv = 1.0f / sqrtf(pok ? pd : 1.0f);
        nx[l] = pok ? px * pinv : nx[l];
        ny[l] = pok ? py * pinv : ny[l];
        nz[l] = pok ? pz * pinv : nz[l];
    }
}

/* shading_normals for the four lanes of a quad form's call. */
static void shading_normals4(const sl_gbuffer_tex_uniforms *u, const sl_fragment_in in[4], const map_values m[4],
                             vec3 out[4])
{
    float vary[SL_GBUFFER_TEX_VARYINGS][4], mx[4], my[4], mz[4], nx[4], ny[4], nz[4];
    const float *v[SL_GBUFFER_TEX_VARYINGS];
    for (int i = 0; i < SL_GBUFFER_TEX_VARYINGS; i++) {
        for (int l = 0; l < 4; l++)
            vary[i][l] = in[l].varyings[i];
        v[i] = vary[i];
    }
    for (int l = 0; l < 4; l++) {
        vec4 nt = m[l].map[SL_MAP_NORMAL];
        mx[l] = nt.x;
        my[l] = nt.y;
        mz[l] = nt.z;
    }
    shading_normals(u, 4, v, mx, my, mz, nx, ny, nz);
    for (int l = 0; l < 4; l++)
        out[l] = vec3(nx[l], ny[l], nz[l]);
}

/* gbuffer_textured.frag after its samples and the normal: the discard (false), the texel. Every
 * form of the shader ends here, so they share every operation after the fetches. */
static bool finish_texel(const sl_gbuffer_tex_uniforms *u, vec3 vWorldPos, float depth, const map_values *m, vec3 n,
                         void *texel)
{
    vec4 kd = m->map[SL_MAP_KD], ks = m->map[SL_MAP_KS], gloss = m->map[SL_MAP_ALPHA];
    vec4 mask = m->map[SL_MAP_MASK];

    if (u->uMaps & SL_GBUFFER_MAP_CUTOFF) {
        float coverage = (u->uMaps & SL_GBUFFER_MAP_MASK) ? mask.x : kd.w;
        if (coverage < u->uAlphaCutoff)
            return false; /* discard */
    }
    sl_gbuffer_texel *g = texel;
    g->position = vWorldPos;
    g->normal = n;
    g->kd = mul3(u->uKd, vec3(kd.x, kd.y, kd.z));
    g->ks = mul3(u->uKs, vec3(ks.x, ks.y, ks.z));
    g->alpha = u->uRoughness >= 0.0f ? sl_gbuffer_ggx_alpha(u->uRoughness * gloss.x) : u->uAlpha * gloss.x;
    g->depth = depth;
    if (u->uMetallic >= 0.0f)
        metallic_roughness(u, m, g);
    return true;
}

/* finish_texel for a fragment of the reference and quad forms: discard, or the extra texel. */
static void finish_fragment(const sl_gbuffer_tex_uniforms *u, const sl_fragment_in *in, const map_values *m, vec3 n,
                            void *texel)
{
    const float *v = in->varyings;
    if (!finish_texel(u, vec3(v[0], v[1], v[2]), in->frag_coord.z, m, n, texel)) {
        discard(in);
        return;
    }
    if (u->extra)
        write_extra(u, in->x, in->y, sl_fragment_stores(in), in->frag_coord.z, m);
}

/* The uniforms of map slot `slot`: its sampler and its uv transform, found by offset (the
 * multi-quad form looks them up for every slot pair in same_fetch and same_plan, each call). */
#define SLOT_FIELDS(F)                                                                                        \
    {offsetof(sl_gbuffer_tex_uniforms, uKd##F), offsetof(sl_gbuffer_tex_uniforms, uKs##F),                     \
     offsetof(sl_gbuffer_tex_uniforms, uAlpha##F), offsetof(sl_gbuffer_tex_uniforms, uNormal##F),              \
     offsetof(sl_gbuffer_tex_uniforms, uMask##F), offsetof(sl_gbuffer_tex_uniforms, uMetallicRoughness##F),    \
     offsetof(sl_gbuffer_tex_uniforms, uOcclusion##F), offsetof(sl_gbuffer_tex_uniforms, uEmissive##F)}
static const size_t sampler_offset[SL_MAP_COUNT] = SLOT_FIELDS(Map), st_offset[SL_MAP_COUNT] = SLOT_FIELDS(MapST);
static inline const sl_sampler2D *map_sampler(const sl_gbuffer_tex_uniforms *u, int slot)
{
    return (const sl_sampler2D *)(const void *)((const char *)u + sampler_offset[slot]);
}
static inline vec4 map_st(const sl_gbuffer_tex_uniforms *u, int slot)
{
    return *(const vec4 *)(const void *)((const char *)u + st_offset[slot]);
}

/* gbuffer_textured.frag: main(). Every map is sampled before the discard, so that each lane of a
 * quad records the same derivative calls (GLSL: derivatives after a discard are undefined). The
 * reference form: one lane at a time through the generic quad rounds (quad.c), each texture()
 * call one derivative record. */
void sl_gbuffer_tex_frag(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    const sl_gbuffer_tex_uniforms *u = uniforms;
    vec2 vTexCoord = vec2(in->varyings[6], in->varyings[7]);
    map_values m;
    maps_unbound(&m);
    for (int slot = 0; slot < SL_MAP_COUNT; slot++)
        if (u->uMaps & (1 << slot))
            m.map[slot] = texture_traced(in, map_sampler(u, slot), map_uv(vTexCoord, map_st(u, slot)), slot, u);
    finish_fragment(u, in, &m, shading_normal(u, in->varyings, m.map[SL_MAP_NORMAL]), texel);
}

/* The quad form of the same shader (sl_program.fragment_quad): one call for the 2x2 quad, so
 * the uv of each map is computed once per lane, its coarse derivatives are the differences of
 * lanes 1 - 0 and 2 - 0 (glsl.h's sl_quad_dfdx_coarse, the expression the rounds use), its
 * level is computed once for the quad (texture() computes the same lambda in every lane), and
 * each lane samples once per map: against the rounds, no second pass and no magnified sample
 * with the first round's zero derivatives. The trace hook runs once per lane with the final
 * values (the rounds also call it in their first round, with zero derivatives; softlight trace
 * keeps the last call of each map, so it prints the same either way). Bit for bit the
 * rounds' result: tests/cli/textured_quad_form.sh compares the G-buffers. */
void sl_gbuffer_tex_frag_quad(const void *uniforms, const sl_fragment_in in[4], void *const texel[4])
{
    const sl_gbuffer_tex_uniforms *u = uniforms;
    map_values m[4];
    for (int l = 0; l < 4; l++)
        maps_unbound(&m[l]);
    for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
        if (!(u->uMaps & (1 << slot)))
            continue;
        const sl_sampler2D *s = map_sampler(u, slot);
        vec4 st = map_st(u, slot);
        vec2 uv[4];
        float us[4], vs[4];
        for (int l = 0; l < 4; l++) {
            uv[l] = map_uv(vec2(in[l].varyings[6], in[l].varyings[7]), st);
            us[l] = uv[l].x;
            vs[l] = uv[l].y;
        }
        vec2 dPdx = vec2(sl_quad_dfdx_coarse(us), sl_quad_dfdx_coarse(vs));
        vec2 dPdy = vec2(sl_quad_dfdy_coarse(us), sl_quad_dfdy_coarse(vs));
        float lambda = sl_texture_lambda_quad(s, dPdx, dPdy, 0.0f);
        vec4 value[4];
        sl_texture_sample4(s, uv, lambda, value); /* the four lanes' sl_texture_sample, one dispatch */
        for (int l = 0; l < 4; l++) {
            m[l].map[slot] = value[l];
            if (u->trace)
                u->trace(u->trace_ctx, &in[l], slot, s, uv[l], dPdx, dPdy, lambda, value[l]);
        }
    }
    vec3 n[4];
    shading_normals4(u, in, m, n);
    for (int l = 0; l < 4; l++)
        finish_fragment(u, &in[l], &m[l], n[l], texel[l]);
}

/* The multi-quad form (sl_program.fragment_quads): the quad form's operations for up to
 * SL_QUADS_MAX quads a call, in structure-of-arrays form, so that each step runs as a vector loop
 * over the lanes (or, for the levels of detail, over the quads): the uv transform of each map,
 * the quads' lambdas (sl_texture_lambda_quads, one per quad from the same coarse differences),
 * the fetches (sl_texture_sample_quads), the normals, the texel's values (finish_lanes). Each lane's
 * values are the quad form's, bit for bit (tests/cli/textured_quad_form.sh compares it with the
 * rounds). The trace hook gets each lane's fetch with the quad form's arguments. */
static void trace_lanes(const sl_gbuffer_tex_uniforms *u, const sl_fragment_quads *q, int slot, const float *us,
                        const float *vs, const float *lambda, float *const rgba[4])
{
    for (int j = 0; j < 4 * q->n; j++) {
        int k = j >> 2, b = j & ~3, x = q->qx[k] + (j & 1), y = q->qy[k] + ((j >> 1) & 1);
        float vary[SL_GBUFFER_TEX_VARYINGS];
        for (int i = 0; i < SL_GBUFFER_TEX_VARYINGS; i++)
            vary[i] = q->varyings[i][j];
        sl_fragment_in in = {.varyings = vary,
                             .frag_coord = vec4((float)x + 0.5f, (float)y + 0.5f, q->frag_z[j], q->frag_w[j]),
                             .front_facing = q->front_facing,
                             .x = x,
                             .y = y,
                             .lane = j & 3,
                             .helper = q->helper[j] != 0};
        vec2 dPdx = vec2(us[b + 1] - us[b], vs[b + 1] - vs[b]), dPdy = vec2(us[b + 2] - us[b], vs[b + 2] - vs[b]);
        u->trace(u->trace_ctx, &in, slot, map_sampler(u, slot), vec2(us[j], vs[j]), dPdx, dPdy, lambda[k],
                 vec4(rgba[0][j], rgba[1][j], rgba[2][j], rgba[3][j]));
    }
}

/* finish_texel (with metallic_roughness) and write_extra for every lane of a multi-quad call:
 * their expressions, operation for operation, as vector loops over the lanes into arrays, then
 * one loop that stores each lane's texel. val[slot][c]: channel c of the slot's fetch (read only
 * for bound slots; an unbound one reads as 1, GL's default texel). */
static const float unbound_lanes[SL_QUAD_LANES] = {
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
_Static_assert(SL_QUAD_LANES == 64, "unbound_lanes holds one 1 per lane");

static void finish_lanes(const sl_gbuffer_tex_uniforms *u, const sl_fragment_quads *q,
                         float (*val)[4][SL_QUAD_LANES], const float *nx, const float *ny, const float *nz)
{
    const int lanes = 4 * q->n;
    const float *map[SL_MAP_COUNT][4];
    for (int slot = 0; slot < SL_MAP_COUNT; slot++)
        for (int c = 0; c < 4; c++)
            map[slot][c] = u->uMaps & (1 << slot) ? val[slot][c] : unbound_lanes;
    _Alignas(64) float kr[SL_QUAD_LANES], kg[SL_QUAD_LANES], kb[SL_QUAD_LANES];
    _Alignas(64) float sr[SL_QUAD_LANES], sg[SL_QUAD_LANES], sb[SL_QUAD_LANES], alpha[SL_QUAD_LANES];
    _Alignas(64) int32_t keep[SL_QUAD_LANES];
    const float *kdr = map[SL_MAP_KD][0], *kdg = map[SL_MAP_KD][1], *kdb = map[SL_MAP_KD][2];
    const float *ksr = map[SL_MAP_KS][0], *ksg = map[SL_MAP_KS][1], *ksb = map[SL_MAP_KS][2];
    const float *gloss = map[SL_MAP_ALPHA][0];
    const float *coverage = u->uMaps & SL_GBUFFER_MAP_MASK ? map[SL_MAP_MASK][0] : map[SL_MAP_KD][3];
    const bool cutoff = (u->uMaps & SL_GBUFFER_MAP_CUTOFF) != 0, ggx = u->uRoughness >= 0.0f;
    const float cut = u->uAlphaCutoff, rough = u->uRoughness, phong = u->uAlpha;
    const vec3 ukd = u->uKd, uks = u->uKs;
#pragma omp simd
    for (int j = 0; j < lanes; j++) {
        keep[j] = !cutoff || !(coverage[j] < cut);
        kr[j] = ukd.x * kdr[j];
        kg[j] = ukd.y * kdg[j];
        kb[j] = ukd.z * kdb[j];
        sr[j] = uks.x * ksr[j];
        sg[j] = uks.y * ksg[j];
        sb[j] = uks.z * ksb[j];
        alpha[j] = ggx ? sl_gbuffer_ggx_alpha(rough * gloss[j]) : phong * gloss[j];
    }
    if (u->uMetallic >= 0.0f) { /* metallic_roughness */
        const float *mg = map[SL_MAP_METALLIC_ROUGHNESS][1], *mb = map[SL_MAP_METALLIC_ROUGHNESS][2];
        const float metallic = u->uMetallic;
#pragma omp simd
        for (int j = 0; j < lanes; j++) {
            float metal = metallic * mb[j], keepf = 1.0f - metal;
            float br = kr[j], bg = kg[j], bb = kb[j];
            kr[j] = br * keepf;
            kg[j] = bg * keepf;
            kb[j] = bb * keepf;
            sr[j] = 0.04f + (br - 0.04f) * metal;
            sg[j] = 0.04f + (bg - 0.04f) * metal;
            sb[j] = 0.04f + (bb - 0.04f) * metal;
            alpha[j] = sl_gbuffer_ggx_alpha(rough * gloss[j] * mg[j]);
        }
    }
    const float *px = q->varyings[0], *py = q->varyings[1], *pz = q->varyings[2];
    for (int j = 0; j < lanes; j++) {
        if (!keep[j]) {
            q->discarded[j] = 1;
            continue;
        }
        sl_gbuffer_texel *g = q->texel[j];
        g->position = vec3(px[j], py[j], pz[j]);
        g->normal = vec3(nx[j], ny[j], nz[j]);
        g->kd = vec3(kr[j], kg[j], kb[j]);
        g->ks = vec3(sr[j], sg[j], sb[j]);
        g->alpha = alpha[j];
        g->depth = q->frag_z[j];
    }
    if (!u->extra)
        return;
    const float *occ = map[SL_MAP_OCCLUSION][0];
    const float *er = map[SL_MAP_EMISSIVE][0], *eg = map[SL_MAP_EMISSIVE][1], *eb = map[SL_MAP_EMISSIVE][2];
    for (int j = 0; j < lanes; j++) {
        if (!keep[j] || q->helper[j]) /* write_extra */
            continue;
        int x = q->qx[j >> 2] + (j & 1), y = q->qy[j >> 2] + ((j >> 1) & 1);
        sl_gbuffer_extra *e = u->extra + (size_t)y * (size_t)u->extra_width + (size_t)x;
        e->occlusion = 1.0f + u->uOcclusionStrength * (occ[j] - 1.0f);
        e->emissive = vec3(u->uEmissive.x * er[j], u->uEmissive.y * eg[j], u->uEmissive.z * eb[j]);
        e->depth = q->frag_z[j];
    }
}

/* The earlier bound slot that samples the same texture with the same sampler state and uv
 * transform as `slot` (glTF's packed occlusion-roughness-metallic image, bound as both the
 * occlusion and the metallic-roughness map), or -1. Its fetch is the same computation on the same
 * inputs, so `slot` can take its values bit for bit. Compared bitwise: 0 and -0 scale differently. */
static int same_fetch(const sl_gbuffer_tex_uniforms *u, int slot)
{
    const sl_sampler2D *s = map_sampler(u, slot);
    const vec4 st = map_st(u, slot);
    for (int k = 0; k < slot; k++) {
        if (!(u->uMaps & (1 << k)))
            continue;
        const sl_sampler2D *o = map_sampler(u, k);
        const vec4 ot = map_st(u, k);
        if (o->texture == s->texture && o->state.min_filter == s->state.min_filter &&
            o->state.mag_filter == s->state.mag_filter && o->state.wrap_s == s->state.wrap_s &&
            o->state.wrap_t == s->state.wrap_t && !memcmp(&o->state.lod_bias, &s->state.lod_bias, sizeof(float)) &&
            !memcmp(&o->state.min_lod, &s->state.min_lod, sizeof(float)) &&
            !memcmp(&o->state.max_lod, &s->state.max_lod, sizeof(float)) && !memcmp(&ot, &st, sizeof st))
            return k;
    }
    return -1;
}

/* The earlier fetched slot (not a same_fetch copy) whose sampler takes the same plan as `slot`'s
 * (sl_texture_same_plan: a map of the same size and sampler state) with the same uv transform, or
 * -1: its lambdas, levels, texel offsets and weights are the ones `slot` would compute, so only
 * its texels are read (pbr.json: the base colour, normal and occlusion-roughness-metallic maps). */
static int same_plan(const sl_gbuffer_tex_uniforms *u, int slot, const int *planned)
{
    const vec4 st = map_st(u, slot);
    for (int k = 0; k < slot; k++) {
        const vec4 ot = map_st(u, k);
        if (planned[k] >= 0 && !memcmp(&ot, &st, sizeof st) &&
            sl_texture_same_plan(map_sampler(u, k), map_sampler(u, slot)))
            return k;
    }
    return -1;
}

void sl_gbuffer_tex_frag_quads(const void *uniforms, const sl_fragment_quads *q)
{
    const sl_gbuffer_tex_uniforms *u = uniforms;
    const int lanes = 4 * q->n;
    _Alignas(64) float val[SL_MAP_COUNT][4][SL_QUAD_LANES];
    /* the plans made so far (SL_GBUFFER_PLANS at most; a slot past them makes its own in `own`),
     * and which one each slot fetched with (-1: none, a copy, or unbound) */
    enum { SL_GBUFFER_PLANS = 3 };
    sl_texture_quads_plan plans[SL_GBUFFER_PLANS], own;
    _Alignas(64) float us[SL_GBUFFER_PLANS][SL_QUAD_LANES], vs[SL_GBUFFER_PLANS][SL_QUAD_LANES];
    _Alignas(64) float own_u[SL_QUAD_LANES], own_v[SL_QUAD_LANES];
    float lambda[SL_GBUFFER_PLANS][SL_QUADS_MAX], own_lambda[SL_QUADS_MAX];
    int planned[SL_MAP_COUNT], plan_count = 0;
    const float *tu = q->varyings[6], *tv = q->varyings[7];
    for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
        planned[slot] = -1;
        if (!(u->uMaps & (1 << slot)))
            continue;
        const int same = u->trace ? -1 : same_fetch(u, slot); /* a trace records every fetch */
        if (same >= 0) {
            for (int c = 0; c < 4; c++)
                memcpy(val[slot][c], val[same][c], (size_t)lanes * sizeof(float));
            continue;
        }
        const sl_sampler2D *s = map_sampler(u, slot);
        float *const rgba[4] = {val[slot][0], val[slot][1], val[slot][2], val[slot][3]};
        const int shared = u->trace ? -1 : same_plan(u, slot, planned);
        if (shared >= 0) {
            planned[slot] = planned[shared];
            sl_texture_fetch_quads(s, &plans[planned[slot]], rgba);
            continue;
        }
        const int k = plan_count < SL_GBUFFER_PLANS ? plan_count++ : -1;
        sl_texture_quads_plan *plan = k >= 0 ? &plans[k] : &own;
        float *pu = k >= 0 ? us[k] : own_u, *pv = k >= 0 ? vs[k] : own_v, *pl = k >= 0 ? lambda[k] : own_lambda;
        const vec4 st = map_st(u, slot);
#pragma omp simd
        for (int j = 0; j < lanes; j++) {
            pu[j] = tu[j] * st.x + st.z; /* map_uv */
            pv[j] = tv[j] * st.y + st.w;
        }
        sl_texture_lambda_quads(s, q->n, pu, pv, 0.0f, pl);
        sl_texture_plan_quads(s, q->n, pu, pv, pl, plan);
        sl_texture_fetch_quads(s, plan, rgba);
        planned[slot] = k;
        if (u->trace)
            trace_lanes(u, q, slot, pu, pv, pl, rgba);
    }
    _Alignas(64) float nx[SL_QUAD_LANES], ny[SL_QUAD_LANES], nz[SL_QUAD_LANES];
    shading_normals(u, lanes, q->varyings, val[SL_MAP_NORMAL][0], val[SL_MAP_NORMAL][1], val[SL_MAP_NORMAL][2], nx, ny,
                    nz);
    finish_lanes(u, q, val, nx, ny, nz);
}

/* Two programs: one that may discard (a late depth test, as GL's rules require) for masked
 * materials, one that cannot and keeps the early test. */
const sl_program sl_gbuffer_tex_program = {
    .vertex = sl_gbuffer_tex_vert,
    .fragment = sl_gbuffer_tex_frag,
    .varying_count = SL_GBUFFER_TEX_VARYINGS,
    .derivatives = true,
    .fragment_quad = sl_gbuffer_tex_frag_quad,
    .quad_writes_texel = true, /* finish_texel sets every field of sl_gbuffer_texel */
    .fragment_quads = sl_gbuffer_tex_frag_quads,
    /* no `stores`: it cannot discard and stores its extra texel at its own pixel, so the last
     * of the rounds overwrites what the earlier rounds stored */
    .writes_depth = true, /* finish_texel's and finish_lanes' g->depth */
};
const sl_program sl_gbuffer_tex_masked_program = {
    .vertex = sl_gbuffer_tex_vert,
    .fragment = sl_gbuffer_tex_frag,
    .varying_count = SL_GBUFFER_TEX_VARYINGS,
    .derivatives = true,
    .discards = true,
    .fragment_quad = sl_gbuffer_tex_frag_quad,
    .quad_writes_texel = true, /* finish_texel sets every field of sl_gbuffer_texel */
    .fragment_quads = sl_gbuffer_tex_frag_quads,
    .stores = true, /* the extra texel: a lane may store it in a round and discard in the next */
    .writes_depth = true, /* finish_texel's and finish_lanes' g->depth */
};

/* A scene map's sampler state: GL's filters for the scene's three names, wrap on both axes. */
sl_sampler_state sl_gbuffer_map_sampler(const sl_material_map *m)
{
    static const sl_wrap wraps[] = {[SL_MAP_REPEAT] = SL_REPEAT, [SL_MAP_CLAMP] = SL_CLAMP_TO_EDGE,
                                    [SL_MAP_MIRROR] = SL_MIRRORED_REPEAT};
    sl_sampler_state s = sl_sampler_default();
    s.wrap_s = s.wrap_t = wraps[m->wrap];
    s.min_filter = m->filter == SL_MAP_TRILINEAR  ? SL_LINEAR_MIPMAP_LINEAR
                   : m->filter == SL_MAP_BILINEAR ? SL_LINEAR
                                                  : SL_NEAREST;
    s.mag_filter = m->filter == SL_MAP_NEAREST ? SL_NEAREST : SL_LINEAR;
    return s;
}

void sl_gbuffer_tex_uniforms_init(sl_gbuffer_tex_uniforms *u, mat4 model, mat4 view_proj, const sl_material *m,
                                  const sl_scene_textures *tex)
{
    memset(u, 0, sizeof *u);
    u->uModel = model;
    u->uViewProj = view_proj;
    u->uNormalMatrix = transpose(inverse(mat3_from_mat4(model)));
    u->uModel3 = mat3_from_mat4(model);
    u->uKd = m->kd;
    u->uKs = m->ks;
    u->uAlpha = m->alpha;
    u->uRoughness = m->brdf == SL_BRDF_GGX ? m->roughness : -1.0f;
    u->uAlphaCutoff = m->alpha_cutoff;
    u->uMetallic = m->brdf == SL_BRDF_GGX && m->metallic >= 0.0f ? m->metallic : -1.0f;
    u->uOcclusionStrength = m->occlusion_strength;
    u->uEmissive = m->emissive;
    sl_sampler2D *samplers[SL_MAP_COUNT] = {&u->uKdMap,     &u->uKsMap,
                                            &u->uAlphaMap,  &u->uNormalMap,
                                            &u->uMaskMap,   &u->uMetallicRoughnessMap,
                                            &u->uOcclusionMap, &u->uEmissiveMap};
    vec4 *st[SL_MAP_COUNT] = {&u->uKdMapST,   &u->uKsMapST,   &u->uAlphaMapST,
                              &u->uNormalMapST, &u->uMaskMapST, &u->uMetallicRoughnessMapST,
                              &u->uOcclusionMapST, &u->uEmissiveMapST};
    for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
        const sl_material_map *map = &m->maps[slot];
        *st[slot] = vec4(1, 1, 0, 0);
        if (!map->set || !tex || map->image < 0 || map->image >= tex->count)
            continue;
        samplers[slot]->texture = tex->textures[map->image];
        samplers[slot]->state = sl_gbuffer_map_sampler(map);
        *st[slot] = vec4(map->uv_scale.x, map->uv_scale.y, map->uv_offset.x, map->uv_offset.y);
        u->uMaps |= 1 << slot;
    }
    if (m->masked)
        u->uMaps |= SL_GBUFFER_MAP_CUTOFF;
}

/* ---- the scene's textures ---- */

bool sl_scene_textures_load(const sl_scene *scene, size_t budget, sl_scene_textures *out, sl_error *err)
{
    memset(out, 0, sizeof *out);
    if (scene->image_count == 0)
        return true;
    out->textures = calloc((size_t)scene->image_count, sizeof *out->textures);
    if (!out->textures)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for %d textures", scene->path, scene->image_count);
    for (int i = 0; i < scene->image_count; i++) {
        const sl_scene_image *img = &scene->images[i];
        bool ok = img->bytes ? sl_texture_load_memory(img->bytes, img->size, img->path, img->srgb, budget,
                                                      &out->textures[i], err)
                             : sl_texture_load(img->path, img->srgb, budget, &out->textures[i], err);
        if (!ok) {
            /* the loader names the file; say which scene and which material's map wanted it */
            sl_error_prefix(err, "%s: %s: ", scene->path, img->used_by);
            sl_scene_textures_free(out);
            return false;
        }
        out->count++;
        out->bytes += sl_texture_bytes(out->textures[i]) + sl_texture_plane_bytes(out->textures[i]);
    }
    return true;
}

void sl_scene_textures_free(sl_scene_textures *t)
{
    if (!t)
        return;
    for (int i = 0; i < t->count; i++)
        sl_texture_destroy(t->textures[i]);
    free(t->textures);
    memset(t, 0, sizeof *t);
}
