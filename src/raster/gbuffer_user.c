/* gbuffer_user.c - a user's G-buffer fragment program (softlight/gbuffer_program.h) as an
 * sl_program: the textured vertex shader (sl_gbuffer_tex_vert) and a fragment shader that hands
 * the user's function the object's material, a zeroed texel and the extra channels at "none",
 * then sets the depth and stores the extra channels where the scene has that plane.
 *
 * It lives apart from the built-in programs so that they stay as they are: the user's function is
 * one opaque call per fragment (no span or quad forms), run through the generic quad rounds when it
 * takes derivatives (quad.c). Its GLSL counterpart is the user's own fragment shader behind
 * shaders/gbuffer_textured.vert in softlight-gl (src/gl/gbuffer_pass.c). */
#include <string.h>

#include "gbuffer_textured.h"
#include "rast_internal.h"

void sl_gbuffer_material_from(sl_gbuffer_material *out, const sl_gbuffer_tex_uniforms *u)
{
    memset(out, 0, sizeof *out);
    out->uModel = u->uModel;
    out->uViewProj = u->uViewProj;
    out->uNormalMatrix = u->uNormalMatrix;
    out->uModel3 = u->uModel3;
    out->uKd = u->uKd;
    out->uKs = u->uKs;
    out->uAlpha = u->uAlpha;
    out->uRoughness = u->uRoughness;
    out->uMetallic = u->uMetallic;
    out->uOcclusionStrength = u->uOcclusionStrength;
    out->uEmissive = u->uEmissive;
    out->uKdMap = u->uKdMap;
    out->uKsMap = u->uKsMap;
    out->uAlphaMap = u->uAlphaMap;
    out->uNormalMap = u->uNormalMap;
    out->uMaskMap = u->uMaskMap;
    out->uMetallicRoughnessMap = u->uMetallicRoughnessMap;
    out->uOcclusionMap = u->uOcclusionMap;
    out->uEmissiveMap = u->uEmissiveMap;
    out->uKdMapST = u->uKdMapST;
    out->uKsMapST = u->uKsMapST;
    out->uAlphaMapST = u->uAlphaMapST;
    out->uNormalMapST = u->uNormalMapST;
    out->uMaskMapST = u->uMaskMapST;
    out->uMetallicRoughnessMapST = u->uMetallicRoughnessMapST;
    out->uOcclusionMapST = u->uOcclusionMapST;
    out->uEmissiveMapST = u->uEmissiveMapST;
    out->uMaps = u->uMaps;
    out->uAlphaCutoff = u->uAlphaCutoff;
}

sl_gbuffer_varyings sl_gbuffer_varyings_of(const sl_fragment_in *in)
{
    const float *v = in->varyings;
    return (sl_gbuffer_varyings){.vWorldPos = vec3(v[0], v[1], v[2]),
                                 .vNormal = vec3(v[3], v[4], v[5]),
                                 .vTexCoord = vec2(v[6], v[7]),
                                 .vTangent = vec4(v[8], v[9], v[10], v[11])};
}

static void user_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    const sl_gbuffer_user_uniforms *u = uniforms;
    sl_gbuffer_tex_vert(&u->tex, in, clip, varyings);
}

static void user_frag(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    const sl_gbuffer_user_uniforms *u = uniforms;
    sl_gbuffer_texel *g = texel;
    memset(g, 0, sizeof *g);
    sl_gbuffer_extra e = {.occlusion = 1.0f};
    u->program->fragment(&u->material, in, g, &e);
    g->depth = in->frag_coord.z;
    /* the extra texel, tagged with the depth (gbuffer.h), where stores take effect and the
     * fragment was kept (a discard marks the quad's lane) */
    if (!u->extra || !sl_fragment_stores(in) || (in->quad && in->quad->discarded[in->lane]))
        return;
    e.depth = in->frag_coord.z;
    u->extra[(size_t)in->y * (size_t)u->extra_width + (size_t)in->x] = e;
}

sl_program sl_gbuffer_user_program(const sl_gbuffer_fragment_program *p, bool extra)
{
    const bool discards = (p->flags & SL_GBUFFER_DISCARDS) != 0;
    return (sl_program){
        .vertex = user_vert,
        .fragment = user_frag,
        .varying_count = SL_GBUFFER_TEX_VARYINGS,
        .derivatives = (p->flags & SL_GBUFFER_DERIVATIVES) != 0,
        .discards = discards,
        /* a lane may store its extra texel in a round and discard in the next; without discards
         * the last round overwrites what the earlier ones stored (sl_program.stores) */
        .stores = extra && discards,
        .writes_depth = true, /* g->depth = frag_coord.z */
    };
}
