/* context.c - a headless OpenGL context: EGL on Mesa's surfaceless platform, no window, no surface.
 *
 * softlight-gl must run where softlight runs (servers, CI), so it never asks for a display: the
 * display comes from EGL_PLATFORM_SURFACELESS_MESA, the context is made current with no surface
 * (EGL_KHR_surfaceless_context) and every pass draws into framebuffer objects. libepoxy resolves
 * the entry points, so a machine without EGL fails here with one line instead of at load time. */
#include <string.h>

#include "slgl.h"

static bool has_extension(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

bool slgl_context_create(slgl_context *ctx, sl_error *err)
{
    memset(ctx, 0, sizeof *ctx);
    ctx->display = EGL_NO_DISPLAY;
    ctx->context = EGL_NO_CONTEXT;
    if (!epoxy_has_egl())
        return sl_fail(err, SL_ERR_GL, "EGL is not available (libEGL could not be loaded)");
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client, "EGL_EXT_platform_base") || !has_extension(client, "EGL_MESA_platform_surfaceless"))
        return sl_fail(err, SL_ERR_GL, "EGL has no surfaceless platform (EGL_MESA_platform_surfaceless)");
    ctx->display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    EGLint major = 0, minor = 0;
    if (ctx->display == EGL_NO_DISPLAY || !eglInitialize(ctx->display, &major, &minor)) {
        ctx->display = EGL_NO_DISPLAY;
        return sl_fail(err, SL_ERR_GL, "EGL: cannot initialise the surfaceless display (error 0x%x)",
                       (unsigned)eglGetError());
    }
    const char *exts = eglQueryString(ctx->display, EGL_EXTENSIONS);
    if (!has_extension(exts, "EGL_KHR_surfaceless_context") || !has_extension(exts, "EGL_KHR_create_context")) {
        slgl_context_destroy(ctx);
        return sl_fail(err, SL_ERR_GL, "EGL %d.%d lacks EGL_KHR_surfaceless_context or EGL_KHR_create_context",
                       major, minor);
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        slgl_context_destroy(ctx);
        return sl_fail(err, SL_ERR_GL, "EGL: desktop OpenGL is not available (eglBindAPI)");
    }
    /* No surface will ever be made, so any config that renders OpenGL will do; without
     * EGL_KHR_no_config_context a config is still needed to create the context. */
    EGLConfig config = NULL;
    EGLint config_count = 0;
    const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
    if (!has_extension(exts, "EGL_KHR_no_config_context") &&
        (!eglChooseConfig(ctx->display, config_attribs, &config, 1, &config_count) || config_count < 1)) {
        slgl_context_destroy(ctx);
        return sl_fail(err, SL_ERR_GL, "EGL: no config renders desktop OpenGL");
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    ctx->context = eglCreateContext(ctx->display, config, EGL_NO_CONTEXT, context_attribs);
    if (ctx->context == EGL_NO_CONTEXT) {
        EGLint code = eglGetError();
        slgl_context_destroy(ctx);
        return sl_fail(err, SL_ERR_GL, "EGL: cannot create an OpenGL 3.3 core context (error 0x%x)",
                       (unsigned)code);
    }
    if (!eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx->context)) {
        EGLint code = eglGetError();
        slgl_context_destroy(ctx);
        return sl_fail(err, SL_ERR_GL, "EGL: cannot make the context current without a surface (error 0x%x)",
                       (unsigned)code);
    }
    ctx->renderer = (const char *)glGetString(GL_RENDERER);
    ctx->version = (const char *)glGetString(GL_VERSION);
    if (!ctx->renderer || !ctx->version || epoxy_gl_version() < 33) {
        slgl_context_destroy(ctx);
        return sl_fail(err, SL_ERR_GL, "OpenGL 3.3 core is not available");
    }
    return true;
}

void slgl_context_destroy(slgl_context *ctx)
{
    if (ctx->display != EGL_NO_DISPLAY) {
        eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (ctx->context != EGL_NO_CONTEXT)
            eglDestroyContext(ctx->display, ctx->context);
        /* No eglTerminate: Mesa 22's surfaceless display frees less than it allocated and unloads
         * the driver, which LeakSanitizer reports as leaks in an unknown module, failing the
         * sanitizer build. The display is reference-free once the context is gone, and the one
         * process that creates it ends right after. */
    }
    memset(ctx, 0, sizeof *ctx);
    ctx->display = EGL_NO_DISPLAY;
    ctx->context = EGL_NO_CONTEXT;
}

bool slgl_check(const char *what, sl_error *err)
{
    GLenum code = glGetError();
    if (code == GL_NO_ERROR)
        return true;
    /* drain the queue so the next check reports the next failure, not this one */
    while (glGetError() != GL_NO_ERROR) {
    }
    return sl_fail(err, SL_ERR_GL, "OpenGL error 0x%04x in %s", (unsigned)code, what);
}
