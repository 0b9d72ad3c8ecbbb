/* program.c - GLSL programs from the files in shaders/, compiled at run time.
 *
 * The shaders are read from disk rather than embedded so that the GLSL that runs is exactly the file
 * a reader diffs against the C port. The directory is shaders/ in softlight's data directory
 * (softlight/data.h: the source tree from a build tree, share/softlight installed) unless
 * $SL_SHADER_DIR names another. A compile or link failure carries the
 * driver's log (first lines) in the error, prefixed with the file name. A fragment shader can be
 * compiled with #defines (lighting.frag's per-scene programs, src/gl/lighting_pass.c).
 *
 * A user's lighting shader (`softlight-gl render --lighting my.frag`) is compiled after lighting.frag
 * itself, its main renamed, so that the user's file sees the built-in's uniforms and functions the
 * way a C lighting program sees the toolbox (docs/lighting-programs.md, "GLSL twins"). The two
 * parts are separate GLSL source-string numbers (#line L S), so the compiler's log names the file
 * the error is in, with that file's own line. A user's G-buffer shader (`--gbuffer-shader my.frag`,
 * src/gl/gbuffer_pass.c) is compiled alone, behind shaders/gbuffer_textured.vert, its errors named
 * the same way. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "slgl.h"
#include "softlight/data.h"

#define SHADER_MAX_BYTES (1u << 20)

/* The full-screen triangle: vertices (-1,-1), (3,-1), (-1,3) cover the viewport once, with no
 * diagonal seam; no vertex buffer, gl_VertexID is enough. */
const char *const slgl_fullscreen_vert = "#version 330 core\n"
                                           "void main()\n"
                                           "{\n"
                                           "    vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), "
                                           "float((gl_VertexID >> 1) * 4 - 1));\n"
                                           "    gl_Position = vec4(p, 0.0, 1.0);\n"
                                           "}\n";

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

/* The compiler's log as one line. With `sources` (NULL: none), only its first line, the first
 * error, and a leading "S:" (Mesa's "S:L(C): error") becomes sources[S] + ":", so the line names the
 * file the error is in. */
static void log_line(char *log, size_t size, const char *const *sources, int source_count)
{
    if (sources)
        log[strcspn(log, "\n")] = '\0';
    for (char *p = log; *p; p++)
        if (*p == '\n')
            *p = ' ';
    for (size_t n = strlen(log); n > 0 && log[n - 1] == ' '; n--)
        log[n - 1] = '\0';
    if (!sources || log[0] < '0' || log[0] >= '0' + source_count || log[1] != ':')
        return;
    char rest[400];
    snprintf(rest, sizeof rest, "%s", log + 2);
    if (snprintf(log, size, "%s:%s", sources[log[0] - '0'], rest) < 0) /* a long path cuts the log short */
        log[0] = '\0';
}

static bool compile_labelled(GLenum type, const char *label, const char *src, const char *const *sources,
                             int source_count, GLuint *shader, sl_error *err)
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
    log_line(log, sizeof log, sources, source_count);
    glDeleteShader(*shader);
    *shader = 0;
    if (sources)
        return sl_fail(err, SL_ERR_FORMAT, "%s", log);
    return sl_fail(err, SL_ERR_GL, "%s: does not compile: %s", label, log);
}

static bool compile(GLenum type, const char *label, const char *src, GLuint *shader, sl_error *err)
{
    return compile_labelled(type, label, src, NULL, 0, shader, err);
}

/* The file's bytes as a NUL-terminated string (malloc'ed). */
static bool read_source(const char *path, char **src, size_t *size, sl_error *err)
{
    unsigned char *bytes = NULL;
    *src = NULL;
    if (!sl_read_file(path, SHADER_MAX_BYTES, &bytes, size, err))
        return false;
    *src = malloc(*size + 1);
    if (!*src) {
        free(bytes);
        return sl_fail(err, SL_ERR_MEMORY, "%s: no memory", path);
    }
    memcpy(*src, bytes, *size);
    (*src)[*size] = '\0';
    free(bytes);
    return true;
}

/* `defines` (NULL: none) go after the file's first line, which GLSL requires to be #version; a
 * #line directive puts the file's own line numbers back into the compiler's log. */
static bool compile_file(GLenum type, const char *name, const char *defines, GLuint *shader, sl_error *err)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", slgl_shader_dir(), name);
    char *src;
    size_t size = 0;
    if (!read_source(path, &src, &size, err))
        return false;
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
    log_line(log, sizeof log, NULL, 0);
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

/* "#version" up to its end of line, at the very start of src; NULL when the first line is not one. */
static const char *after_version(const char *src)
{
    const char *eol = strchr(src, '\n');
    return strncmp(src, "#version 330", 12) == 0 && eol ? eol + 1 : NULL;
}

bool slgl_program_user_lighting(const char *vert_label, const char *vert_src, const char *user_path,
                                const char *frag_defines, GLuint *program, sl_error *err)
{
    *program = 0;
    struct stat st;
    if (stat(user_path, &st) != 0)
        return sl_fail(err, SL_ERR_IO, "%s: %s", user_path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return sl_fail(err, SL_ERR_IO, "%s: not a regular file", user_path);
    char builtin_path[1200];
    snprintf(builtin_path, sizeof builtin_path, "%s/lighting.frag", slgl_shader_dir());
    char *user = NULL, *builtin = NULL, *full = NULL;
    size_t user_size = 0, builtin_size = 0;
    bool ok = false;
    if (!read_source(user_path, &user, &user_size, err) || !read_source(builtin_path, &builtin, &builtin_size, err))
        goto done;
    const char *user_body = after_version(user), *builtin_body = after_version(builtin);
    if (!user_body || strlen(user) != user_size) {
        sl_fail(err, SL_ERR_FORMAT, "%s: %s", user_path,
                user_body ? "holds a NUL byte: not GLSL source" : "the first line must be #version 330 core");
        goto done;
    }
    if (!builtin_body) {
        sl_fail(err, SL_ERR_FORMAT, "%s: the first line is not #version 330", builtin_path);
        goto done;
    }
    /* source string 1: lighting.frag, its main renamed; source string 0: the user's file */
    static const char head[] = "#version 330 core\n";
    static const char rename[] = "\n#define main sl_builtin_lighting_main\n#line 2 1\n";
    static const char restore[] = "\n#undef main\n#line 2 0\n";
    const char *defines = frag_defines ? frag_defines : "";
    size_t n = strlen(head) + strlen(defines) + strlen(rename) + strlen(builtin_body) + strlen(restore) +
               strlen(user_body) + 1;
    full = malloc(n);
    if (!full) {
        sl_fail(err, SL_ERR_MEMORY, "%s: no memory", user_path);
        goto done;
    }
    snprintf(full, n, "%s%s%s%s%s%s", head, defines, rename, builtin_body, restore, user_body);
    const char *sources[2] = {user_path, builtin_path};
    GLuint vert, frag;
    if (!compile(GL_VERTEX_SHADER, vert_label, vert_src, &vert, err))
        goto done;
    if (!compile_labelled(GL_FRAGMENT_SHADER, user_path, full, sources, 2, &frag, err)) {
        glDeleteShader(vert);
        goto done;
    }
    ok = link(vert, frag, user_path, program, err);
done:
    free(user);
    free(builtin);
    free(full);
    return ok;
}

bool slgl_program_with_fragment_file(const char *vert_name, const char *frag_path, GLuint *program, sl_error *err)
{
    *program = 0;
    struct stat st;
    if (stat(frag_path, &st) != 0)
        return sl_fail(err, SL_ERR_IO, "%s: %s", frag_path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return sl_fail(err, SL_ERR_IO, "%s: not a regular file", frag_path);
    char *src = NULL;
    size_t size = 0;
    if (!read_source(frag_path, &src, &size, err))
        return false;
    const char *sources[1] = {frag_path};
    GLuint vert, frag;
    bool ok = false;
    if (strlen(src) != size)
        sl_fail(err, SL_ERR_FORMAT, "%s: holds a NUL byte: not GLSL source", frag_path);
    else if (compile_file(GL_VERTEX_SHADER, vert_name, NULL, &vert, err)) {
        if (compile_labelled(GL_FRAGMENT_SHADER, frag_path, src, sources, 1, &frag, err))
            ok = link(vert, frag, frag_path, program, err);
        else
            glDeleteShader(vert);
    }
    free(src);
    return ok;
}
