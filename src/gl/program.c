/* program.c - GLSL programs from the files in shaders/, compiled at run time.
 *
 * The shaders are read from disk rather than embedded so that the GLSL that runs is exactly the file
 * a reader diffs against the C port. The directory is shaders/ in softlight's data directory
 * (softlight/data.h: the source tree from a build tree, share/softlight installed) unless
 * $SL_SHADER_DIR names another. A compile or link failure carries the
 * driver's log (first lines) in the error, prefixed with the file name. A fragment shader can be
 * compiled with #defines (lighting.frag's per-scene programs, src/gl/lighting_pass.c), or read
 * from a path of the user's (--gbuffer-shader, src/gl/gbuffer_pass.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "slgl.h"
#include "softlight/data.h"

#define SHADER_MAX_BYTES (1u << 20)

const char *slgl_shader_dir(void)
{
    static char dir_buf[SL_PATH_MAX];
    const char *dir = getenv("SL_SHADER_DIR");
    if (dir && dir[0])
        return dir;
    if (!sl_data_path("shaders", dir_buf, sizeof dir_buf))
        return "shaders"; /* no data directory: relative to the current one */
    return dir_buf;
}

static bool compile(GLenum type, const char *label, const char *src, GLuint *shader, sl_error *err)
{
    *shader = glCreateShader(type);
    glShaderSource(*shader, 1, &src, NULL);
    glCompileShader(*shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(*shader, GL_COMPILE_STATUS, &ok);
    if (ok)
        return true;
    char log[400] = "";
    glGetShaderInfoLog(*shader, (GLsizei)sizeof log, NULL, log);
    for (char *p = log; *p; p++)
        if (*p == '\n')
            *p = ' ';
    glDeleteShader(*shader);
    *shader = 0;
    return sl_fail(err, SL_ERR_GL, "%s: does not compile: %s", label, log);
}

/* `defines` (NULL: none) go after the file's first line, which GLSL requires to be #version; a
 * #line directive puts the file's own line numbers back into the compiler's log. */
static bool compile_path(GLenum type, const char *path, const char *defines, GLuint *shader, sl_error *err)
{
    unsigned char *bytes = NULL;
    size_t size = 0;
    if (!sl_read_file(path, SHADER_MAX_BYTES, &bytes, &size, err))
        return false;
    char *src = malloc(size + 1);
    if (!src) {
        free(bytes);
        return sl_fail(err, SL_ERR_MEMORY, "%s: no memory", path);
    }
    memcpy(src, bytes, size);
    src[size] = '\0';
    free(bytes);
    bool ok;
    char *eol = strchr(src, '\n');
    if (defines && (strncmp(src, "#version", 8) != 0 || !eol)) {
        ok = sl_fail(err, SL_ERR_FORMAT, "%s: defines given, but the first line is not #version", path);
    } else if (defines) {
        const char *head = "\n#line 2\n";
        size_t version = (size_t)(eol + 1 - src), nd = strlen(defines), nh = strlen(head);
        char *full = malloc(size + nd + nh + 1);
        if (!full) {
            free(src);
            return sl_fail(err, SL_ERR_MEMORY, "%s: no memory", path);
        }
        memcpy(full, src, version);
        memcpy(full + version, defines, nd);
        memcpy(full + version + nd, head, nh);
        memcpy(full + version + nd + nh, src + version, size - version + 1);
        ok = compile(type, path, full, shader, err);
        free(full);
    } else {
        ok = compile(type, path, src, shader, err);
    }
    free(src);
    return ok;
}

static bool compile_file(GLenum type, const char *name, const char *defines, GLuint *shader, sl_error *err)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", slgl_shader_dir(), name);
    return compile_path(type, path, defines, shader, err);
}

static bool link(GLuint vert, GLuint frag, const char *label, GLuint *program, sl_error *err)
{
    *program = glCreateProgram();
    glAttachShader(*program, vert);
    glAttachShader(*program, frag);
    glLinkProgram(*program);
    glDeleteShader(vert);
    glDeleteShader(frag);
    GLint ok = GL_FALSE;
    glGetProgramiv(*program, GL_LINK_STATUS, &ok);
    if (ok)
        return true;
    char log[400] = "";
    glGetProgramInfoLog(*program, (GLsizei)sizeof log, NULL, log);
    for (char *p = log; *p; p++)
        if (*p == '\n')
            *p = ' ';
    glDeleteProgram(*program);
    *program = 0;
    return sl_fail(err, SL_ERR_GL, "%s: does not link: %s", label, log);
}

bool slgl_program_from_files(const char *vert_name, const char *frag_name, GLuint *program, sl_error *err)
{
    GLuint vert, frag;
    *program = 0;
    if (!compile_file(GL_VERTEX_SHADER, vert_name, NULL, &vert, err))
        return false;
    if (!compile_file(GL_FRAGMENT_SHADER, frag_name, NULL, &frag, err)) {
        glDeleteShader(vert);
        return false;
    }
    return link(vert, frag, frag_name, program, err);
}

bool slgl_program_from_sources(const char *vert_label, const char *vert_src, const char *frag_name,
                               const char *frag_defines, GLuint *program, sl_error *err)
{
    GLuint vert, frag;
    *program = 0;
    if (!compile(GL_VERTEX_SHADER, vert_label, vert_src, &vert, err))
        return false;
    if (!compile_file(GL_FRAGMENT_SHADER, frag_name, frag_defines, &frag, err)) {
        glDeleteShader(vert);
        return false;
    }
    return link(vert, frag, frag_name, program, err);
}

bool slgl_program_with_fragment_file(const char *vert_name, const char *frag_path, GLuint *program, sl_error *err)
{
    GLuint vert, frag;
    *program = 0;
    if (!compile_file(GL_VERTEX_SHADER, vert_name, NULL, &vert, err))
        return false;
    if (!compile_path(GL_FRAGMENT_SHADER, frag_path, NULL, &frag, err)) {
        glDeleteShader(vert);
        return false;
    }
    return link(vert, frag, frag_path, program, err);
}
