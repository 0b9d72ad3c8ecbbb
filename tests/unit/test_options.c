/* test_options.c - the option declaration (core/options.h) against everything that reads it or
 * describes it, so that a default, a limit or a name cannot drift: the command line's arguments
 * (src/app/render_options.c, linked into this test), the programs' --help, the scene reader's keys,
 * defaults and ranges, one resolution (command line over scene file over default), the library's
 * mode names and defaults, the stages' own limits (the G-buffer's largest side, the Hammersley
 * set's size), README.md's option table and docs/scene-format.md's key tables. */
#include "testutil.h"

#include <ctype.h>
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
        /* the rows with a command-line spelling come first (--help's order), then the scene file's only */
        assert_true(o->cli != NULL || o->scene[0] != NULL);
        if (id > 0 && !sl_options[id - 1].cli)
            assert_null(o->cli);
        assert_true(o->cli ? o->help != NULL : true);
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
    int n = sl_render_options_table(ro, table);
    char *argv[] = {"softlight", "render", (char *)a, (char *)b, NULL};
    const char *positional[1];
    int npos;
    bool help;
    return sl_args_parse(b ? 4 : 3, argv, 2, table, n, positional, 1, &npos, &help, err) &&
           sl_render_options_desc(ro, desc, err);
}

/* A record's value of row `id` (`which`: a size's width or height), as a double. */
static double field_value(sl_option_values *v, int id, int which)
{
    void *f = sl_option_field(v, (sl_option_id)id);
    switch (sl_options[id].type) {
    case SL_OPTION_FLAG: return *(bool *)f ? 1.0 : 0.0;
    case SL_OPTION_INT:
    case SL_OPTION_CHOICE: return *(int *)f;
    case SL_OPTION_FLOAT: return (double)*(float *)f;
    case SL_OPTION_SIZE: return ((int *)f)[which];
    }
    return -1.0;
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
    int n = sl_render_options_table(&ro, table), k = 0;
    for (int id = 0; id < SL_OPT_COUNT; id++) {
        const sl_option *o = &sl_options[id];
        if (!o->cli)
            continue;
        assert_true(k < n);
        const sl_arg *a = &table[k++];
        assert_string_equal(a->help, o->help);
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
            assert_int_equal((int)field_value(&d.options, id, 0), v);
            assert_int_equal(d.options.set, SL_OPT_BIT(id));
        }
    }
    assert_int_equal(k, n);
}

static void test_cli_limits_are_the_table_s(void **state)
{
    (void)state;
    for (int id = 0; id < SL_OPT_COUNT; id++) {
        const sl_option *o = &sl_options[id];
        if (!o->cli || (o->type != SL_OPTION_INT && o->type != SL_OPTION_SIZE))
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

/* The scene's value for the key `which` of row `id`; the row's bit must say whether the file gave it. */
static double scene_value(sl_scene *s, int id, int which)
{
    return field_value(&s->options, id, which);
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
            /* absent: the default, not marked as given */
            assert_true(scene_value(&s, id, which) == (double)(float)o->def[which]);
            assert_false(sl_option_is_set(&s.options, (sl_option_id)id));
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
                snprintf(want, sizeof want, "t.json: %s: %g is outside %d..%d", path, hi + 1, (int)lo, (int)hi);
                expect_scene_error(path, hi + 1, want);
                snprintf(want, sizeof want, "t.json: %s: %g is outside %d..%d", path, lo - 1, (int)lo, (int)hi);
                expect_scene_error(path, lo - 1, want);
            } else {
                snprintf(want, sizeof want, "t.json: %s: %g is outside %g..%g", path, hi * 2, lo, hi);
                expect_scene_error(path, hi * 2, want);
            }
        }
    }
    /* render.width, height, samples, exposure, contrast, srgb, lod, distortion, gterm, estimator,
     * irradiance, env_layout, diffuse_only, specular_only, no_lights, rotate, frame, env_lights,
     * ao_radius, reflection_occlusion, sky_maps, shadows; environment.intensity */
    assert_int_equal(keys, 23);
    sl_scene_free(&s);
    expect_scene_text_error("render.diffuse_only", "true, \"specular_only\": true",
                            "t.json: render.diffuse_only and render.specular_only exclude each other");
}

/* ---- one resolution: the command line over the scene file over the default ---- */

static void test_resolution_order(void **state)
{
    (void)state;
    sl_scene s;
    sl_error err = {0};
    assert_true(parse_scene("{\"render\": {\"samples\": 20, \"estimator\": \"mf\", \"rotate\": true, "
                            "\"env_lights\": 4}}", &s, &err));
    sl_render_desc d = {0};
    assert_true(sl_render_desc_resolve(&d, &s, &err));
    assert_int_equal(d.lighting.samples, 20);
    assert_int_equal(d.lighting.estimator, SL_ESTIMATOR_MICROFACET);
    assert_true(d.lighting.rotate);
    assert_int_equal(d.lighting.env_lights, 4);
    assert_int_equal(d.lighting.lod_rule, (int)sl_options[SL_OPT_LOD].def[0]);
    assert_int_equal(d.lighting.irradiance, (int)sl_options[SL_OPT_IRRADIANCE].def[0]);
    assert_int_equal(d.width, (int)sl_options[SL_OPT_SIZE].def[0]);
    assert_true(d.tonemap.exposure == (float)sl_options[SL_OPT_EXPOSURE].def[0]);
    assert_int_equal(d.options.set, s.options.set);
    assert_true(sl_render_desc_resolve(&d, &s, &err)); /* resolving again changes nothing */
    assert_int_equal(d.lighting.samples, 20);

    sl_render_options ro;
    assert_true(parse_args(&ro, &d, "-n", "7", &err));
    assert_true(sl_render_desc_resolve(&d, &s, &err));
    assert_int_equal(d.lighting.samples, 7);
    assert_int_equal(d.lighting.estimator, SL_ESTIMATOR_MICROFACET);
    assert_true(parse_args(&ro, &d, "--estimator=spec", NULL, &err));
    assert_true(sl_render_desc_resolve(&d, &s, &err));
    assert_int_equal(d.lighting.estimator, SL_ESTIMATOR_SPEC);
    assert_int_equal(d.lighting.samples, 20);
    /* --diffuse-only: the lighting's specular term and point lights off */
    assert_true(parse_args(&ro, &d, "--diffuse-only", NULL, &err));
    assert_true(d.options.diffuse_only);
    assert_true(sl_render_desc_resolve(&d, &s, &err));
    assert_true(d.lighting.no_specular && d.lighting.no_point_lights && !d.lighting.no_diffuse);
    sl_scene_free(&s);

    /* a scene's precomputed map is the irradiance unless one is chosen */
    assert_true(parse_scene("{\"environment\": {\"hdr\": \"a.hdr\", \"irradiance\": \"i.hdr\"}}", &s, &err));
    d = (sl_render_desc){0};
    assert_true(sl_render_desc_resolve(&d, &s, &err));
    assert_int_equal(d.lighting.irradiance, SL_IRRADIANCE_MAP);
    assert_true(parse_args(&ro, &d, "--irradiance", "sh9", &err));
    assert_true(sl_render_desc_resolve(&d, &s, &err));
    assert_int_equal(d.lighting.irradiance, SL_IRRADIANCE_SH9);
    sl_scene_free(&s);

    /* the command line's flag and the scene's exclude each other too */
    assert_true(parse_scene("{\"render\": {\"specular_only\": true}}", &s, &err));
    assert_true(parse_args(&ro, &d, "--diffuse-only", NULL, &err));
    assert_false(sl_render_desc_resolve(&d, &s, &err));
    assert_non_null(strstr(err.msg, "exclude each other"));
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
    assert_int_equal((int)est->max, SL_ESTIMATOR_CV_MIS);
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

/* ---- the descriptions: --help, README.md, docs/scene-format.md ---- */

/* A file of the source tree (the tests run in it; SL_SOURCE_DIR names it otherwise), whole. */
static char *read_text(const char *name)
{
    const char *dir = getenv("SL_SOURCE_DIR");
    char path[1024];
    snprintf(path, sizeof path, "%s%s%s", dir ? dir : "", dir ? "/" : "", name);
    FILE *f = fopen(path, "rb");
    if (!f) {
        print_error("cannot open %s\n", path);
        fail();
    }
    char *text = calloc(1, 1 << 20);
    assert_non_null(text);
    size_t n = fread(text, 1, (1 << 20) - 1, f);
    text[n] = '\0';
    fclose(f);
    return text;
}

/* The rows of the first markdown table at or after the line `heading`: each line starting with '|',
 * past the header and its rule, up to the first line that does not. Returns how many; each row's
 * cells (trimmed, "\|" kept as '|') in cells[row][col]. */
#define MAX_ROWS 64
#define MAX_COLS 6
#define CELL 640
typedef char table_cells[MAX_ROWS][MAX_COLS][CELL];
static int read_table(const char *text, const char *heading, table_cells cells)
{
    const char *h = strstr(text, heading);
    if (!h) {
        print_error("no heading '%s'\n", heading);
        fail();
    }
    const char *line = heading[0] == '|' ? h : strstr(h, "\n|"); /* the heading may be the table's header */
    assert_non_null(line);
    line += *line == '\n';
    int rows = -2; /* the header and its rule */
    while (*line == '|') {
        const char *end = strchr(line, '\n');
        if (!end)
            end = line + strlen(line);
        if (rows >= 0) {
            assert_true(rows < MAX_ROWS);
            int col = 0;
            size_t n = 0;
            char *cell = cells[rows][0];
            for (const char *c = line + 1; c < end && col < MAX_COLS; c++) {
                if (*c == '\\' && c[1] == '|') {
                    if (n < CELL - 1)
                        cell[n++] = '|';
                    c++;
                } else if (*c == '|') {
                    while (n && cell[n - 1] == ' ')
                        n--;
                    cell[n] = '\0';
                    if (++col < MAX_COLS)
                        cell = cells[rows][col], n = 0;
                } else if (n || *c != ' ') {
                    if (n < CELL - 1)
                        cell[n++] = *c;
                }
            }
        }
        rows++;
        line = *end ? end + 1 : end;
    }
    return rows;
}

/* The words of a choice row, min .. max, each once, in any order in `list` ("a|b|c"). */
static bool same_names(const sl_option *o, const char *list, char sep)
{
    int count = 0;
    for (const char *p = list; *p;) {
        const char *e = strchr(p, sep);
        size_t n = e ? (size_t)(e - p) : strlen(p);
        int v;
        char word[32];
        if (n >= sizeof word)
            return false;
        memcpy(word, p, n);
        word[n] = '\0';
        if (!sl_option_parse(o, word, &v) || v < (int)o->min)
            return false;
        count++;
        p = e ? e + 1 : p + n;
    }
    return count == (int)(o->max - o->min) + 1;
}

/* README.md's option table: each option with a command-line spelling is in a first cell once,
 * as `[ALIAS, ]FLAG[ METAVAR or its choices]`, and nothing else is; a range "A..B" or a "default
 * N" in the meaning of a row of one option is the row's. */
static void test_readme_agrees(void **state)
{
    (void)state;
    char *text = read_text("README.md");
    static table_cells cells;
    int rows = read_table(text, "| option | meaning |", cells);
    assert_true(rows > 0);
    int seen[SL_OPT_COUNT] = {0};
    for (int r = 0; r < rows; r++) {
        int in_row = 0, last = -1;
        for (char *p = strchr(cells[r][0], '`'); p; p = strchr(p, '`')) {
            char *e = strchr(p + 1, '`');
            assert_non_null(e);
            char item[256];
            snprintf(item, sizeof item, "%.*s", (int)(e - p - 1), p + 1);
            p = e + 1;
            char *alias = NULL, *flag = item, *arg = NULL;
            char *comma = strstr(item, ", ");
            if (comma) {
                *comma = '\0';
                alias = item;
                flag = comma + 2;
            }
            char *space = strchr(flag, ' ');
            if (space) {
                *space = '\0';
                arg = space + 1;
            }
            int id = 0;
            while (id < SL_OPT_COUNT && !(sl_options[id].cli && !strcmp(sl_options[id].cli, flag)))
                id++;
            if (id == SL_OPT_COUNT) {
                print_error("README.md: `%s` is not an option of the declaration\n", flag);
                fail();
            }
            const sl_option *o = &sl_options[id];
            seen[id]++;
            in_row++;
            last = id;
            bool ok = (alias == NULL) == (o->alias == NULL) && (!alias || !strcmp(alias, o->alias));
            if (o->type == SL_OPTION_FLAG)
                ok = ok && !arg;
            else if (o->type == SL_OPTION_CHOICE)
                ok = ok && arg && same_names(o, arg, '|');
            else
                ok = ok && arg && !strcmp(arg, o->metavar);
            if (!ok) {
                print_error("README.md: `%s%s%s%s%s` disagrees with the declaration's %s%s%s %s\n", alias ? alias : "",
                            alias ? ", " : "", flag, arg ? " " : "", arg ? arg : "", o->alias ? o->alias : "",
                            o->alias ? ", " : "", o->cli, o->metavar ? o->metavar : "(its choices or nothing)");
                fail();
            }
        }
        if (in_row != 1)
            continue;
        const sl_option *o = &sl_options[last];
        const char *meaning = cells[r][1];
        int lo, hi, def;
        for (const char *p = meaning; (p = strpbrk(p, "0123456789")); p++) {
            if ((p == meaning || !isdigit((unsigned char)p[-1])) && sscanf(p, "%d..%d", &lo, &hi) == 2 &&
                (lo != (int)o->min || hi != (int)o->max)) {
                print_error("README.md: %s: %d..%d, the declaration %g..%g\n", o->cli, lo, hi, o->min, o->max);
                fail();
            }
        }
        const char *d = strstr(meaning, "default ");
        if (d && o->type == SL_OPTION_INT && sscanf(d, "default %d", &def) == 1 && def != (int)o->def[0]) {
            print_error("README.md: %s: default %d, the declaration %g\n", o->cli, def, o->def[0]);
            fail();
        }
    }
    for (int id = 0; id < SL_OPT_COUNT; id++)
        if (sl_options[id].cli && seen[id] != 1) {
            print_error("README.md: %s appears %d times in the option table, expected once\n", sl_options[id].cli,
                        seen[id]);
            fail();
        }
    free(text);
}

/* Whether the backquoted words of `cell` are exactly the choice's names ("default" with them where
 * 0 means the default). */
static bool cell_names(const sl_option *o, const char *cell)
{
    char list[256] = "";
    size_t n = 0;
    bool with_default = false;
    for (const char *p = strchr(cell, '`'); p; p = strchr(p, '`')) {
        const char *e = strchr(p + 1, '`');
        if (!e)
            return false;
        if ((size_t)(e - p - 1) == 7 && !strncmp(p + 1, "default", 7))
            with_default = true;
        else
            n += (size_t)snprintf(list + n, sizeof list - n, "%s%.*s", n ? "|" : "", (int)(e - p - 1), p + 1);
        p = e + 1;
    }
    return same_names(o, list, '|') && with_default == (o->min > 0 && o->names[0] != NULL);
}

/* docs/scene-format.md: each scene key of the declaration is a row of its section's table (the
 * `render` keys: nothing else is), with the type, default and range the declaration gives. */
static void test_scene_format_agrees(void **state)
{
    (void)state;
    char *text = read_text("docs/scene-format.md");
    static table_cells cells;
    static const char *const type_word[] = {[SL_OPTION_FLAG] = "boolean", [SL_OPTION_INT] = "integer",
                                            [SL_OPTION_FLOAT] = "number", [SL_OPTION_SIZE] = "integer",
                                            [SL_OPTION_CHOICE] = "string"};
    const char *const sections[] = {"render", "environment"};
    for (int sec = 0; sec < 2; sec++) {
        char heading[64];
        snprintf(heading, sizeof heading, "\n## `%s`\n", sections[sec]);
        int rows = read_table(text, heading, cells);
        size_t plen = strlen(sections[sec]);
        int keys = 0;
        for (int id = 0; id < SL_OPT_COUNT; id++)
            for (int which = 0; which < 2 && sl_options[id].scene[which]; which++) {
                const sl_option *o = &sl_options[id];
                const char *path = o->scene[which];
                if (strncmp(path, sections[sec], plen) || path[plen] != '.')
                    continue;
                keys++;
                char key[64];
                snprintf(key, sizeof key, "`%s`", path + plen + 1);
                int r = 0;
                while (r < rows && strcmp(cells[r][0], key))
                    r++;
                if (r == rows) {
                    print_error("docs/scene-format.md: no row for %s\n", path);
                    fail();
                }
                const char *type = cells[r][1], *def = cells[r][2], *range = cells[r][3];
                bool ok = !strcmp(type, type_word[o->type]);
                double lo = sl_option_file_min(o), hi = sl_option_file_max(o), x, y;
                char want[128];
                switch (o->type) {
                case SL_OPTION_FLAG: ok = ok && !strcmp(def, "`false`") && !strcmp(range, "`true`, `false`"); break;
                case SL_OPTION_CHOICE:
                    snprintf(want, sizeof want, "`\"%s\"`", o->names[(int)o->def[0]]);
                    ok = ok && strstr(def, want) && cell_names(o, range);
                    break;
                case SL_OPTION_INT:
                case SL_OPTION_SIZE:
                case SL_OPTION_FLOAT:
                    ok = ok && sscanf(def, "`%lf`", &x) == 1 && x == o->def[which];
                    if (o->file_min_open)
                        ok = ok && sscanf(range, "(%lf, %lf]", &x, &y) == 2 && x == lo && y == hi;
                    else
                        ok = ok && sscanf(range, "%lf .. %lf", &x, &y) == 2 && x == lo && y == hi;
                    break;
                }
                if (!ok) {
                    print_error("docs/scene-format.md: %s: '%s | %s | %s' disagrees with the declaration (%s, "
                                "default %g, %g..%g)\n", path, type, def, range, type_word[o->type], o->def[which],
                                lo, hi);
                    fail();
                }
            }
        if (sec == 0 && rows != keys) {
            print_error("docs/scene-format.md: the render table has %d rows, the declaration %d render keys\n", rows,
                        keys);
            fail();
        }
    }
    free(text);
}

/* Each program's --help lists every option with a spelling: its alias, flag, metavar or choices,
 * and its help line, as the declaration has them (SL_BUILD_DIR names the built programs). */
static void test_help_agrees(void **state)
{
    (void)state;
    const char *dir = getenv("SL_BUILD_DIR");
    if (!dir)
        skip();
    const char *const commands[] = {"softlight render", "softlight trace", "softlight info", "softlight-gl render"};
    for (size_t c = 0; c < sizeof commands / sizeof commands[0]; c++) {
        char cmd[1200], program[1100];
        snprintf(program, sizeof program, "%s/%.*s", dir, (int)strcspn(commands[c], " "), commands[c]);
        FILE *exists = fopen(program, "rb");
        if (!exists)
            continue; /* softlight-gl is built only with EGL */
        fclose(exists);
        snprintf(cmd, sizeof cmd, "%s/%s --help", dir, commands[c]);
        FILE *p = popen(cmd, "r");
        assert_non_null(p);
        char *out = calloc(1, 1 << 16);
        assert_non_null(out);
        size_t n = fread(out, 1, (1 << 16) - 1, p);
        out[n] = '\0';
        assert_int_equal(pclose(p), 0);
        for (int id = 0; id < SL_OPT_COUNT; id++) {
            const sl_option *o = &sl_options[id];
            if (!o->cli)
                continue;
            char words[128], left[256], line[1024];
            assert_true(sl_option_choices(o, words, sizeof words));
            const char *meta = o->type == SL_OPTION_CHOICE ? words : o->metavar ? o->metavar : "";
            snprintf(left, sizeof left, "%s%s%s%s%s", o->alias ? o->alias : "", o->alias ? ", " : "", o->cli,
                     meta[0] ? " " : "", meta);
            snprintf(line, sizeof line, "\n  %-34s %s\n", left, o->help);
            if (!strstr(out, line)) {
                print_error("%s --help lacks the line%s", commands[c], line);
                fail();
            }
        }
        free(out);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_are_well_formed),
        cmocka_unit_test(test_cli_reads_the_table),
        cmocka_unit_test(test_cli_limits_are_the_table_s),
        cmocka_unit_test(test_scene_reads_the_table),
        cmocka_unit_test(test_library_reads_the_table),
        cmocka_unit_test(test_resolution_order),
        cmocka_unit_test(test_readme_agrees),
        cmocka_unit_test(test_scene_format_agrees),
        cmocka_unit_test(test_help_agrees),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
