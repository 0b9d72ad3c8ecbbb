/* textures.c - the scene's textures in OpenGL: each of softlight's decoded images (the
 * renderer's sl_scene_textures, loaded once per scene) uploaded with the same format, and the
 * sampler state of one material's map.
 *
 * Level 0 goes up as softlight stores it (row 0 = bottom: sl_texture_load has already flipped
 * the file, texture.h), in the GL format of the same name, and GL makes the rest of the chain
 * with glGenerateMipmap: what a GL application does, and what softlight's mips reproduce
 * (texture.h: llvmpipe's bytes for UNORM, within one code for sRGB). Sampler state lives in
 * sampler objects, one per texture unit, set per draw from sl_gbuffer_map_sampler, the same
 * function the C program's uniforms take it from. */
#include <stdlib.h>
#include <string.h>

#include "slgl.h"

typedef struct {
    GLenum internal, format, type;
} gl_format;

/* sl_texture_format -> glTexImage2D's three enums (the formats texture.h names after GL's). */
static gl_format format_of(sl_texture_format f)
{
    switch (f) {
    case SL_TEX_R8: return (gl_format){GL_R8, GL_RED, GL_UNSIGNED_BYTE};
    case SL_TEX_RG8: return (gl_format){GL_RG8, GL_RG, GL_UNSIGNED_BYTE};
    case SL_TEX_RGB8: return (gl_format){GL_RGB8, GL_RGB, GL_UNSIGNED_BYTE};
    case SL_TEX_RGBA8: return (gl_format){GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
    case SL_TEX_SRGB8: return (gl_format){GL_SRGB8, GL_RGB, GL_UNSIGNED_BYTE};
    case SL_TEX_SRGB8_ALPHA8: return (gl_format){GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE};
    case SL_TEX_R16: return (gl_format){GL_R16, GL_RED, GL_UNSIGNED_SHORT};
    case SL_TEX_RG16: return (gl_format){GL_RG16, GL_RG, GL_UNSIGNED_SHORT};
    case SL_TEX_RGB16: return (gl_format){GL_RGB16, GL_RGB, GL_UNSIGNED_SHORT};
    case SL_TEX_RGBA16: return (gl_format){GL_RGBA16, GL_RGBA, GL_UNSIGNED_SHORT};
    case SL_TEX_R32F: return (gl_format){GL_R32F, GL_RED, GL_FLOAT};
    case SL_TEX_RGB32F: return (gl_format){GL_RGB32F, GL_RGB, GL_FLOAT};
    case SL_TEX_RGBA32F: return (gl_format){GL_RGBA32F, GL_RGBA, GL_FLOAT};
    }
    return (gl_format){GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
}

bool slgl_textures_upload(const sl_scene_textures *in, slgl_textures *out, sl_error *err)
{
    memset(out, 0, sizeof *out);
    if (in->count == 0)
        return true;
    out->names = calloc((size_t)in->count, sizeof *out->names);
    if (!out->names)
        return sl_fail(err, SL_ERR_MEMORY, "no memory for %d texture names", in->count);
    out->count = in->count;
    glGenTextures(in->count, out->names);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1); /* rows are tightly packed, whatever their width */
    for (int i = 0; i < in->count; i++) {
        const sl_texture *t = in->textures[i];
        int w = 0, h = 0;
        const void *texels = sl_texture_level_texels(t, 0, &w, &h);
        gl_format f = format_of(sl_texture_get_format(t));
        glBindTexture(GL_TEXTURE_2D, out->names[i]);
        glTexImage2D(GL_TEXTURE_2D, 0, (GLint)f.internal, w, h, 0, f.format, f.type, texels);
        glGenerateMipmap(GL_TEXTURE_2D); /* sl_texture_load always builds the whole chain too */
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    return slgl_check("uploading the scene's textures", err);
}

void slgl_textures_destroy(slgl_textures *t)
{
    if (t->names)
        glDeleteTextures(t->count, t->names);
    free(t->names);
    memset(t, 0, sizeof *t);
}

static GLint gl_filter(sl_filter f)
{
    static const GLint filters[] = {[SL_NEAREST] = GL_NEAREST,
                                    [SL_LINEAR] = GL_LINEAR,
                                    [SL_NEAREST_MIPMAP_NEAREST] = GL_NEAREST_MIPMAP_NEAREST,
                                    [SL_LINEAR_MIPMAP_NEAREST] = GL_LINEAR_MIPMAP_NEAREST,
                                    [SL_NEAREST_MIPMAP_LINEAR] = GL_NEAREST_MIPMAP_LINEAR,
                                    [SL_LINEAR_MIPMAP_LINEAR] = GL_LINEAR_MIPMAP_LINEAR};
    return filters[f];
}

static GLint gl_wrap(sl_wrap w)
{
    return w == SL_CLAMP_TO_EDGE ? GL_CLAMP_TO_EDGE : w == SL_MIRRORED_REPEAT ? GL_MIRRORED_REPEAT : GL_REPEAT;
}

void slgl_sampler_set(GLuint sampler, const sl_sampler_state *s)
{
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, gl_filter(s->min_filter));
    glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, gl_filter(s->mag_filter));
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, gl_wrap(s->wrap_s));
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, gl_wrap(s->wrap_t));
    glSamplerParameterf(sampler, GL_TEXTURE_LOD_BIAS, s->lod_bias);
    glSamplerParameterf(sampler, GL_TEXTURE_MIN_LOD, s->min_lod);
    glSamplerParameterf(sampler, GL_TEXTURE_MAX_LOD, s->max_lod);
}
