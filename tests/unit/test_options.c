/* test_options.c - the option table (core/options.h) against everything that reads it, so that
 * a default, a limit or a name cannot drift: the command line's arguments (src/app/render_options.c,
 * linked into this test) and their help lines, the scene reader's keys, defaults and ranges, the
 * library's mode names and defaults, and the stages' own limits (the G-buffer's largest side,
 * the Hammersley set's size). */
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/render_options.h"
#include "core/options.h"
#include "post/tonemap.h"
#include "raster/gbuffer.h"
#include "scene/scene.h"
#include "shading/lighting.h"

/* ---- the table itself ---- */

static void test_rows_are_well_formed(void **state)
{
    (void)state;
    for (int id = 0; id < SL_OPT_COUNT; id++) {
        const sl_option *o = &sl_options[id];
        assert_non_null(o->name);
        assert_true(o->min <= o->max);
        /* the first SL_OPT_CLI_COUNT rows are the command line's, the rest a scene file's only */
        assert_true(id < SL_OPT_CLI_COUNT ? o->cli != NULL : o->cli == NULL && o->scene[0] != NULL);
        for (int k = 0; k < id; k++) {
            assert_string_not_equal(o->name, sl_options[k].name);
            if (o->cli && sl_options[k].cli)
                assert_string_not_equal(o->cli, sl_options[k].cli);
        }
        if (o->file_min != 0.0 || o->file_max != 0.0)
            assert_true(o->file_min < o->file_max && o->file_max <= o->max);
        switch (o->type) {
        case SL_OPTION_FLAG: assert_true(o->def[0] == 0.0 && o->min == 0.0 && o->max == 0.0); break;
        case SL_OPTION_INT:
        case SL_OPTION_FLOAT: /* 0 may stand for "the stage decides" (threads: all cores) */
            assert_true(o->def[0] == 0.0 || (o->def[0] >= o->min && o->def[0] <= o->max));
            break;
        case SL_OPTION_SIZE:
            for (int i = 0; i < 2; i++) {
                assert_true(o->def[i] >= o->min && o->def[i] <= o->max);
                assert_non_null(o->scene[i]);
            }
            break;
        case SL_OPTION_CHOICE:
            assert_true(o->def[0] >= o->min && o->def[0] <= o->max);
            for (int v = (int)o->min; v <= (int)o->max; v++) {
                int back = -1;
                assert_non_null(o->names[v]);
                assert_true(sl_option_parse(o, o->names[v], &back));
                assert_int_equal(back, v);
            }
            break;
        }
    }
}

/* ---- the command line ---- */

static bool parse_args(sl_render_options *ro, sl_render_desc *desc, const char *a, const char *b, sl_error *err)
{
    sl_arg table[SL_RENDER_OPTION_COUNT];
    sl_render_options_table(ro, table);
    char *argv[] = {"softlight", "render", (char *)a, (char *)b, NULL};
    const char *positional[1];
    int npos;
    bool help;
    return sl_args_parse(b ? 4 : 3, argv, 2, table, SL_RENDER_OPTION_COUNT, positional, 1, &npos, &help, err) &&
           sl_render_options_desc(ro, desc, err);
}

/* A range "(A..B" or a default "default NAME" written in a help line must be the row's. */
static void check_help(const sl_option *o, const char *help)
{
    const char *range = strstr(help, "(");
    int lo, hi;
    if (range && sscanf(range, "(%d..%d", &lo, &hi) == 2) {
        if (lo != (int)o->min || hi != (int)o->max) {
            print_error("%s: help says %d..%d, the table %g..%g\n", o->cli, lo, hi, o->min, o->max);
            fail();
        }
    }
    const char *def = strstr(help, "(default ");
    if (def && o->type == SL_OPTION_CHOICE && def[9] != ':' && def[9] != ')') {
        const char *name = sl_option_name(o, (int)o->def[0]);
        if (strncmp(def + 9, name, strlen(name))) {
            print_error("%s: help says '%s', the table's default is %s\n", o->cli, def, name);
            fail();
        }
    }
}

static void test_cli_reads_the_table(void **state)
{
    (void)state;
    sl_render_options ro;
    sl_arg table[SL_RENDER_OPTION_COUNT];
    sl_render_options_table(&ro, table);
    for (int id = 0; id < SL_OPT_CLI_COUNT; id++) {
        const sl_option *o = &sl_options[id];
        const sl_arg *a = &table[id];
        assert_string_equal(a->name, o->cli);
        if (o->alias)
            assert_string_equal(a->alias, o->alias);
        else
            assert_null(a->alias);
        check_help(o, a->help);
        if (o->type == SL_OPTION_INT || o->type == SL_OPTION_FLOAT || o->type == SL_OPTION_SIZE) {
            assert_true(a->min == o->min && a->max == o->max);
        }
        if (o->type != SL_OPTION_CHOICE)
            continue;
        char words[128];
        assert_true(sl_option_choices(o, words, sizeof words));
        assert_string_equal(a->choices, words);
        /* every word reaches the renderer's description as the value the table gives it */
        for (int v = (int)o->min; v <= (int)o->max; v++) {
            sl_render_desc d;
            sl_error err = {0};
            assert_true(parse_args(&ro, &d, o->cli, o->names[v], &err));
            int got = id == SL_OPT_LOD         ? (int)d.lighting.lod_rule
                      : id == SL_OPT_GTERM     ? (int)d.lighting.gterm
                      : id == SL_OPT_ESTIMATOR ? (int)d.lighting.estimator
                      : id == SL_OPT_IRRADIANCE ? (int)d.lighting.irradiance
                      : id == SL_OPT_ENV_LAYOUT ? (int)d.lighting.env_layout
                                                : -1;
            assert_int_equal(got, v);
            if (id == SL_OPT_IRRADIANCE)
                assert_true(d.irradiance_set);
        }
    }
}

static void test_cli_limits_are_the_table_s(void **state)
{
    (void)state;
    for (int id = 0; id < SL_OPT_CLI_COUNT; id++) {
        const sl_option *o = &sl_options[id];
        if (o->type != SL_OPTION_INT && o->type != SL_OPTION_SIZE)
            continue;
        char in[64], above[64], below[64];
        int lo = (int)o->min, hi = (int)o->max;
        if (o->type == SL_OPTION_SIZE) {
            snprintf(in, sizeof in, "%dx%d", hi, lo);
            snprintf(above, sizeof above, "%dx%d", hi + 1, lo);
            snprintf(below, sizeof below, "%dx%d", hi, lo - 1);
        } else {
            snprintf(in, sizeof in, "%d", id == SL_OPT_TILE ? hi : lo); /* a tile is a power of two */
            snprintf(above, sizeof above, "%d", hi + 1);
            snprintf(below, sizeof below, "%d", lo - 1);
        }
        sl_render_options ro;
        sl_render_desc d;
        sl_error err = {0};
        if (!parse_args(&ro, &d, o->cli, in, &err)) {
            print_error("%s %s: %s\n", o->cli, in, err.msg);
            fail();
        }
        assert_false(parse_args(&ro, &d, o->cli, above, &err));
        assert_false(parse_args(&ro, &d, o->cli, below, &err));
    }
}

/* ---- the scene reader ---- */

static bool parse_scene(const char *json, sl_scene *s, sl_error *err)
{
    return sl_scene_parse(json, strlen(json), "t.json", "", false, s, err);
}

/* The scene's value for the key `which` of row `id`. */
static double scene_value(const sl_scene *s, int id, int which)
{
    switch (id) {
    case SL_OPT_SIZE: return which ? s->settings.height : s->settings.width;
    case SL_OPT_SAMPLES: return s->settings.samples;
    case SL_OPT_EXPOSURE: return (double)s->settings.exposure;
    case SL_OPT_CONTRAST: return (double)s->settings.contrast;
    case SL_OPT_ENV_INTENSITY: return (double)s->environment.intensity;
    case SL_OPT_LOD: return (double)s->settings.lod;
    case SL_OPT_GTERM: return (double)s->settings.gterm;
    case SL_OPT_ESTIMATOR: return (double)s->settings.estimator;
    case SL_OPT_ENV_LAYOUT: return (double)s->settings.env_layout;
    case SL_OPT_IRRADIANCE: return (double)s->settings.irradiance;
    case SL_OPT_DISTORTION: return s->settings.distortion ? 1.0 : 0.0;
    case SL_OPT_ROTATE: return s->settings.rotate ? 1.0 : 0.0;
    default: break;
    }
    print_error("row %s has a scene key this test does not know: add it here\n", sl_options[id].name);
    fail();
    return 0.0;
}

/* {"render": {"samples": VALUE}} for the path "render.samples" (an environment needs its hdr). */
static void scene_json(char *out, size_t size, const char *path, const char *value)
{
    const char *dot = strchr(path, '.');
    assert_non_null(dot);
    snprintf(out, size, "{\"%.*s\": {%s\"%s\": %s}}", (int)(dot - path), path,
             strncmp(path, "environment.", 12) ? "" : "\"hdr\": \"a.hdr\", ", dot + 1, value);
}

/* The key at `path` given `text` (JSON) reads as `want`. */
static void expect_scene_reads(const char *path, int id, int which, const char *text, double want)
{
    char json[256];
    scene_json(json, sizeof json, path, text);
    sl_scene s;
    sl_error err = {0};
    if (!parse_scene(json, &s, &err)) {
        print_error("%s: %s\n", json, err.msg);
        fail();
    }
    assert_true(scene_value(&s, id, which) == want);
    sl_scene_free(&s);
}

/* The key at `path` given `text` (JSON) fails with an error containing `want`. */
static void expect_scene_text_error(const char *path, const char *text, const char *want)
{
    char json[256];
    scene_json(json, sizeof json, path, text);
    sl_scene s;
    sl_error err = {0};
    if (parse_scene(json, &s, &err) || !strstr(err.msg, want)) {
        print_error("%s: expected an error containing '%s', got '%s'\n", json, want, err.msg);
        fail();
    }
}

static void expect_scene_value(const char *path, int id, int which, double value)
{
    char text[64];
    snprintf(text, sizeof text, "%.17g", value);
    expect_scene_reads(path, id, which, text, (double)(float)value);
}

/* A choice key given by name ("render.estimator": "splitsum") reads as `value`. */
static void expect_scene_choice(const char *path, int id, const char *name, int value)
{
    char text[64];
    snprintf(text, sizeof text, "\"%s\"", name);
    expect_scene_reads(path, id, 0, text, (double)value);
}

static void expect_scene_error(const char *path, double value, const char *want)
{
    char text[64];
    snprintf(text, sizeof text, "%.17g", value);
    expect_scene_text_error(path, text, want);
}

static void test_scene_reads_the_table(void **state)
{
    (void)state;
    sl_scene s;
    sl_error err = {0};
    assert_true(parse_scene("{\"environment\": {\"hdr\": \"a.hdr\"}}", &s, &err));
    int keys = 0;
    for (int id = 0; id < SL_OPT_COUNT; id++) {
        const sl_option *o = &sl_options[id];
        for (int which = 0; which < 2 && o->scene[which]; which++, keys++) {
            const char *path = o->scene[which];
            double lo = sl_option_file_min(o), hi = sl_option_file_max(o);
            char want[160];
            /* the default; an irradiance not named is -1: the environment's map if it names one,
             * else the option's default (sl_render_desc_resolve) */
            double absent = id == SL_OPT_IRRADIANCE ? -1.0 : (double)(float)o->def[which];
            assert_true(scene_value(&s, id, which) == absent);
            if (o->type == SL_OPTION_FLAG) {
                expect_scene_reads(path, id, 0, "true", 1.0);
                expect_scene_reads(path, id, 0, "false", 0.0);
                snprintf(want, sizeof want, "t.json: %s: expected true or false", path);
                expect_scene_text_error(path, "1", want);
                continue;
            }
            if (o->type == SL_OPTION_CHOICE) {
                /* every name the command line takes, "default" where 0 means it, and no other word */
                for (int v = 0; v <= (int)o->max; v++) {
                    if (v < (int)o->min && !(v == 0 && o->names[0]))
                        continue;
                    expect_scene_choice(path, id, o->names[v], v);
                }
                char words[96];
                assert_true(sl_option_choices(o, words, sizeof words));
                snprintf(want, sizeof want, "t.json: %s: unknown %s \"fast\" (expected %s)", path, o->name, words);
                expect_scene_text_error(path, "\"fast\"", want);
                snprintf(want, sizeof want, "t.json: %s: expected a string", path);
                expect_scene_text_error(path, "1", want);
                continue;
            }
            /* the range, at both ends and past them */
            expect_scene_value(path, id, which, hi);
            if (o->file_min_open) {
                expect_scene_value(path, id, which, lo + (hi - lo) / 1024);
                snprintf(want, sizeof want, "t.json: %s: %g must be greater than %g", path, lo, lo);
                expect_scene_error(path, lo, want);
            } else {
                expect_scene_value(path, id, which, lo);
            }
            if (o->type == SL_OPTION_INT || o->type == SL_OPTION_SIZE) {
                snprintf(want, sizeof want, "t.json: %s: %d is outside %d..%d", path, (int)hi + 1, (int)lo, (int)hi);
                expect_scene_error(path, hi + 1, want);
                snprintf(want, sizeof want, "t.json: %s: %d is outside %d..%d", path, (int)lo - 1, (int)lo, (int)hi);
                expect_scene_error(path, lo - 1, want);
            } else {
                snprintf(want, sizeof want, "t.json: %s: %g is outside %g..%g", path, hi * 2, lo, hi);
                expect_scene_error(path, hi * 2, want);
            }
        }
    }
    /* render.width, height, samples, exposure, contrast, lod, gterm, estimator, env_layout,
     * irradiance, distortion, rotate; environment.intensity */
    assert_int_equal(keys, 13);
    sl_scene_free(&s);
}

/* ---- the library's names, defaults and limits ---- */

static void test_library_reads_the_table(void **state)
{
    (void)state;
    const sl_option *lod = &sl_options[SL_OPT_LOD], *est = &sl_options[SL_OPT_ESTIMATOR];
    const sl_option *g = &sl_options[SL_OPT_GTERM], *irr = &sl_options[SL_OPT_IRRADIANCE];
    for (int v = 0; v <= (int)lod->max; v++)
        assert_string_equal(sl_lod_rule_name((sl_lod_rule)v), lod->names[v]);
    for (int v = 0; v <= (int)est->max; v++)
        assert_string_equal(sl_estimator_name((sl_estimator)v), est->names[v]);
    for (int v = 0; v <= (int)g->max; v++)
        assert_string_equal(sl_gterm_name((sl_gterm)v), g->names[v]);
    for (int v = 0; v <= (int)irr->max; v++)
        assert_string_equal(sl_irradiance_name((sl_irradiance_method)v), irr->names[v]);
    assert_string_equal(sl_lod_rule_name((sl_lod_rule)(SL_LOD_PDF + 1)), "?");
    /* the GLSL's values (shaders/lighting.frag) are the last of each list */
    assert_int_equal((int)lod->max, SL_LOD_PDF);
    assert_int_equal((int)est->max, SL_ESTIMATOR_SPLITSUM);
    assert_int_equal((int)g->max, SL_GTERM_ONE);
    assert_int_equal((int)irr->max, SL_IRRADIANCE_DP);
    assert_int_equal(sl_option_next(lod, SL_LOD_PDF), SL_LOD_NONE);
    assert_int_equal(sl_option_next(g, SL_GTERM_INV_LH2), SL_GTERM_ONE);

    /* zero resolves to the table's defaults */
    sl_lighting_options r = sl_lighting_options_resolve(NULL);
    assert_int_equal(r.samples, (int)sl_options[SL_OPT_SAMPLES].def[0]);
    assert_int_equal(r.lod_rule, (int)lod->def[0]);
    assert_int_equal(r.estimator, (int)est->def[0]);
    assert_int_equal(r.gterm, (int)g->def[0]);
    assert_true(r.env_intensity == (float)sl_options[SL_OPT_ENV_INTENSITY].def[0]);
    sl_image in = {0}, by_zero = {0}, by_table = {0};
    sl_error err = {0};
    assert_true(sl_image_alloc(&in, 2, 1, 3, &err));
    for (int i = 0; i < 6; i++)
        in.data[i] = 0.25f * (float)i;
    sl_tonemap_options explicit_defaults = {.exposure = (float)sl_options[SL_OPT_EXPOSURE].def[0],
                                            .contrast = (float)sl_options[SL_OPT_CONTRAST].def[0]};
    assert_true(sl_tonemap_image(&in, &by_zero, &(sl_tonemap_options){0}, 0, &err));
    assert_true(sl_tonemap_image(&in, &by_table, &explicit_defaults, 0, &err));
    assert_memory_equal(by_zero.data, by_table.data, 6 * sizeof(float));
    sl_image_free(&in);
    sl_image_free(&by_zero);
    sl_image_free(&by_table);

    /* one limit per quantity: the stages refuse exactly past the table's maximum */
    sl_gbuffer gb = {0};
    assert_true(sl_gbuffer_resize(&gb, (int)sl_options[SL_OPT_SIZE].max, 1, &err));
    assert_false(sl_gbuffer_resize(&gb, (int)sl_options[SL_OPT_SIZE].max + 1, 1, &err));
    sl_gbuffer_free(&gb);
    sl_hammersley *set = malloc(sizeof *set);
    assert_non_null(set);
    assert_true(sl_hammersley_build(set, (int)sl_options[SL_OPT_SAMPLES].max, &err));
    assert_false(sl_hammersley_build(set, (int)sl_options[SL_OPT_SAMPLES].max + 1, &err));
    free(set);
    assert_int_equal((int)sl_options[SL_OPT_ENV_LIGHTS].max, SL_ENV_LIGHTS_MAX);
    assert_int_equal((int)sl_options[SL_OPT_TILE].min, SL_TILE_MIN);
    assert_int_equal((int)sl_options[SL_OPT_TILE].max, SL_TILE_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_are_well_formed),
        cmocka_unit_test(test_cli_reads_the_table),
        cmocka_unit_test(test_cli_limits_are_the_table_s),
        cmocka_unit_test(test_scene_reads_the_table),
        cmocka_unit_test(test_library_reads_the_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
