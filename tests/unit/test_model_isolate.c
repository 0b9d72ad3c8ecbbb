/* test_model_isolate.c - the import's child process (scene/model_isolate.c): a model comes back
 * whole, an error comes back as it was, and a child that crashes, runs out of time or out of
 * memory becomes one error line while the test process goes on. */
#include "testutil.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene/model.h"
#include "scene/scene_internal.h"

/* Two meshes (one with texture coordinates and tangents), two instances, one embedded image. */
static bool make_model(void *ctx, sl_model *m, sl_error *err)
{
    (void)ctx, (void)err;
    memset(m, 0, sizeof *m);
    snprintf(m->path, sizeof m->path, "made.glb");
    m->mesh_count = 2;
    m->meshes = calloc(2, sizeof *m->meshes);
    for (int i = 0; i < 2; i++) {
        sl_mesh *s = &m->meshes[i].mesh;
        s->vertex_count = 3 + i;
        s->triangle_count = 1 + i;
        s->positions = calloc((size_t)s->vertex_count, sizeof *s->positions);
        s->normals = calloc((size_t)s->vertex_count, sizeof *s->normals);
        s->indices = calloc((size_t)s->triangle_count * 3, sizeof *s->indices);
        for (int v = 0; v < s->vertex_count; v++) {
            s->positions[v] = vec3((float)v, (float)i, 0.5f);
            s->normals[v] = vec3(0, 0, 1);
        }
        for (int k = 0; k < s->triangle_count * 3; k++)
            s->indices[k] = (uint32_t)(k % s->vertex_count);
        if (i == 1) {
            s->texcoords = calloc((size_t)s->vertex_count, sizeof *s->texcoords);
            s->tangents = calloc((size_t)s->vertex_count, sizeof *s->tangents);
            s->texcoords[2] = vec2(0.25f, 0.75f);
            s->tangents[3] = vec4(1, 0, 0, -1);
        }
    }
    m->instance_count = 2;
    m->instances = calloc(2, sizeof *m->instances);
    m->instances[1].mesh = 1;
    m->instances[1].world.c[3].x = 7.0f;
    m->material_count = 1;
    m->materials = calloc(1, sizeof *m->materials);
    snprintf(m->materials[0].name, sizeof m->materials[0].name, "clay");
    m->materials[0].roughness = 0.375f;
    m->image_count = 1;
    m->images = calloc(1, sizeof *m->images);
    m->images[0].embedded = 0;
    m->images[0].size = 5;
    m->images[0].bytes = malloc(5);
    memcpy(m->images[0].bytes, "\x89PNG!", 5);
    m->has_camera = true;
    m->camera.fovy_deg = 33.0f;
    return true;
}

static void test_model_round_trip(void **state)
{
    (void)state;
    sl_model m;
    sl_error err = {0};
    assert_true(sl_scene_import_isolated(make_model, NULL, "made.glb", (size_t)256 << 20, 10, &m, &err));
    assert_string_equal(m.path, "made.glb");
    assert_int_equal(m.mesh_count, 2);
    assert_int_equal(m.meshes[1].mesh.vertex_count, 4);
    assert_int_equal(m.meshes[1].mesh.triangle_count, 2);
    assert_null(m.meshes[0].mesh.texcoords);
    assert_null(m.meshes[0].mesh.tangents);
    assert_true(m.meshes[1].mesh.positions[3].x == 3.0f && m.meshes[1].mesh.positions[3].y == 1.0f);
    assert_true(m.meshes[1].mesh.texcoords[2].y == 0.75f);
    assert_true(m.meshes[1].mesh.tangents[3].w == -1.0f);
    assert_int_equal(m.meshes[1].mesh.indices[5], 1);
    assert_int_equal(m.instance_count, 2);
    assert_int_equal(m.instances[1].mesh, 1);
    assert_true(m.instances[1].world.c[3].x == 7.0f);
    assert_string_equal(m.materials[0].name, "clay");
    assert_true(m.materials[0].roughness == 0.375f);
    assert_int_equal(m.image_count, 1);
    assert_memory_equal(m.images[0].bytes, "\x89PNG!", 5);
    assert_true(m.has_camera && m.camera.fovy_deg == 33.0f);
    sl_model_free(&m);
}

static bool fail_plainly(void *ctx, sl_model *m, sl_error *err)
{
    (void)ctx, (void)m;
    return sl_fail(err, SL_ERR_FORMAT, "bad.obj: line 3: expected a number");
}

static bool crash(void *ctx, sl_model *m, sl_error *err)
{
    (void)ctx, (void)m, (void)err;
    __builtin_trap();
}

static bool hang(void *ctx, sl_model *m, sl_error *err)
{
    (void)ctx, (void)m, (void)err;
    for (;;)
        pause();
    return false;
}

#if defined(__SANITIZE_ADDRESS__)
#define ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ASAN 1
#endif
#endif
#ifndef ASAN
#define ASAN 0
#endif

#if !ASAN /* AddressSanitizer's builds bound time only (model_isolate.c) */
/* Touches far more memory than the budget, as an importer that trusts a declared count does;
 * fails like assimp (an error, not a crash) when an allocation is refused. */
static char *volatile held[64]; /* escapes the optimiser: clang drops an allocation nobody keeps */

static bool hog(void *ctx, sl_model *m, sl_error *err)
{
    (void)ctx, (void)m;
    for (int i = 0; i < 64; i++) {
        char *p = malloc((size_t)64 << 20);
        if (!p)
            return sl_fail(err, SL_ERR_MEMORY, "hog: std::bad_alloc");
        memset(p, 1, (size_t)64 << 20);
        held[i] = p;
    }
    return sl_fail(err, SL_ERR_FORMAT, "hog: every allocation succeeded");
}
#endif

static void expect(scene_import_fn fn, int seconds, const char *want)
{
    sl_model m;
    sl_error err = {0};
    assert_false(sl_scene_import_isolated(fn, NULL, "f.off", (size_t)128 << 20, seconds, &m, &err));
    if (!strstr(err.msg, want) || strchr(err.msg, '\n'))
        fail_msg("expected one line with \"%s\", got \"%s\"", want, err.msg);
    assert_int_equal(m.mesh_count, 0);
}

static void test_failures(void **state)
{
    (void)state;
    expect(fail_plainly, 10, "bad.obj: line 3: expected a number");
    expect(crash, 10, "f.off: the importer crashed on this file (signal");
    expect(hang, 1, "f.off: the import took more than the 1 s");
    /* AddressSanitizer's builds bound time only (model_isolate.c). */
#if !ASAN
    expect(hog, 20, "f.off: the import needs more than the 128 MiB");
#endif
}

/* An importer that prints on its own (OpenGEX's parser writes to std::cerr) before it fails. */
static bool chatter(void *ctx, sl_model *m, sl_error *err)
{
    (void)ctx, (void)m;
    fputs("nullptr returned by creating DDLNode.\n", stderr);
    fflush(stderr);
    printf("and on stdout\n");
    fflush(stdout);
    return sl_fail(err, SL_ERR_FORMAT, "f.ogex: Validation failed");
}

#if ASAN
/* A heap overflow in the import: the sanitizer's report must still reach stderr. */
static char *volatile sink;
static bool overflow(void *ctx, sl_model *m, sl_error *err)
{
    (void)ctx, (void)m, (void)err;
    sink = malloc(8);
    sink[8] = 1;
    return false;
}
#endif

/* What the child prints goes nowhere: the error comes back, and this process's stderr and stdout
 * (a file here) stay empty. In a sanitized build a sanitizer's report from the child still
 * reaches stderr. */
static void test_child_output(void **state)
{
    (void)state;
    fflush(stdout);
    fflush(stderr);
    int saved_out = dup(STDOUT_FILENO), saved_err = dup(STDERR_FILENO);
    FILE *f = tmpfile();
    assert_true(saved_out >= 0 && saved_err >= 0 && f);
    dup2(fileno(f), STDOUT_FILENO);
    dup2(fileno(f), STDERR_FILENO);
    sl_model m;
    sl_error err = {0};
    bool ok = sl_scene_import_isolated(chatter, NULL, "f.ogex", (size_t)128 << 20, 10, &m, &err);
#if ASAN
    sl_error err2 = {0};
    bool ok2 = sl_scene_import_isolated(overflow, NULL, "f.off", (size_t)128 << 20, 20, &m, &err2);
#endif
    fflush(stdout);
    fflush(stderr);
    dup2(saved_out, STDOUT_FILENO);
    dup2(saved_err, STDERR_FILENO);
    close(saved_out);
    close(saved_err);
    char text[8192] = "";
    rewind(f);
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    assert_false(ok);
    assert_string_equal(err.msg, "f.ogex: Validation failed");
    if (strstr(text, "DDLNode") || strstr(text, "on stdout"))
        fail_msg("the child's own printing reached this process: \"%s\"", text);
#if ASAN
    assert_false(ok2);
    if (!strstr(text, "AddressSanitizer"))
        fail_msg("no sanitizer report from the child; got \"%.200s\"", text);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_model_round_trip),
        cmocka_unit_test(test_failures),
        cmocka_unit_test(test_child_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
