/* view_keys.c - the viewer's one key table (the contract is in view_internal.h): what each
 * input does, as the help overlay (F1) shows it, as `softlight view --keys` prints it for
 * docs/viewer.md (tests/cli/view_keys.sh checks the doc against it), and the script's spelling
 * of each key (`key NAME`, which the same test runs through the script parser).
 *
 * The cycles of the option keys (L, K, G) are spelled from the option table (core/options.h),
 * the irradiance cycle from the order view_input.c steps through, so neither can drift from
 * what the keys do. No SDL here. */
#include "view_internal.h"

#include <stdio.h>
#include <string.h>

/* What I steps through: oct -> dp -> sh9 -> brute -> map (when the scene names one) -> oct. */
const sl_irradiance_method view_irradiance_cycle[VIEW_IRRADIANCE_CYCLE] = {
    SL_IRRADIANCE_OCT, SL_IRRADIANCE_DP, SL_IRRADIANCE_SH9, SL_IRRADIANCE_BRUTE, SL_IRRADIANCE_MAP,
};

typedef struct {
    const char *input;  /* as the help and the doc show it */
    const char *script; /* the script's commands that give it, "|"-separated; "" for none */
    const char *action; /* {lod}, {estimator}, {gterm}, {irradiance}, {views} expand to their cycles */
} key_row;

static const key_row rows[] = {
    {"left drag", "drag X0 Y0 X1 Y1 left", "orbit: the camera turns about +Z through the target and tilts (0.4 degrees a pixel)"},
    {"right or middle drag", "drag X0 Y0 X1 Y1 right|drag X0 Y0 X1 Y1 middle",
     "pan: the scene follows the pointer at the target's depth"},
    {"wheel", "wheel N", "zoom (distance x 0.9 a click), held between the model's bounds and 10 x the framing distance"},
    {"Left / Right", "key Left|key Right", "orbit: the camera moves left / right about +Z, 5 degrees (shift: 1)"},
    {"Up / Down", "key Up|key Down", "orbit: the camera rises / sinks, 5 degrees (shift: 1)"},
    {"A / D", "key a|key d", "pan: the camera moves left / right, 5% of the view height (shift: 1%)"},
    {"W / S", "key w|key s", "pan: the camera moves up / down, 5% of the view height (shift: 1%)"},
    {"+ / -", "key +|key -", "zoom in / out, as a wheel click"},
    {"F", "key f", "frame the model: its bounding sphere fills the view, direction kept"},
    {"R", "key r", "reset every setting to the scene's (and the command line's): camera, N, exposure, contrast, "
                   "toggles, rules, estimator, irradiance, environment rotation, view"},
    {"E / Q", "key e|key q", "exposure up / down by a quarter stop (x 2^(1/4))"},
    {"C / X", "key c|key x", "contrast up / down by 0.1 (the tone map's exponent c/2.2)"},
    {"N / B", "key n|key b", "samples N up / down: powers of two 1..1024 and the scene's N"},
    {"] / [", "key ]|key [", "rotate the environment about +Z by +15 / -15 degrees"},
    {"1 2 3", "key 1|key 2|key 3", "toggle the diffuse term, the specular term, the point lights"},
    {"I", "key i", "irradiance: {irradiance}"},
    {"O", "key o", "ambient occlusion on / off (the radius of --ao-radius or the scene's, else a tenth of the "
                   "scene's bounding radius)"},
    {"U", "key u", "shadow maps of every point light, and of the env lights when they are on, on / off "
                   "(--shadows; a light's own \"shadow\" key keeps it casting)"},
    {"Y", "key y", "sky visibility maps on / off (the count of --sky-maps or the scene's, else 32)"},
    {"J", "key j", "reflection occlusion on / off (the distance of --reflection-occlusion or the scene's, else "
                   "half the scene's bounding diagonal)"},
    {"L", "key l", "mip-level rule: {lod} (both lobe sets')"},
    {"K", "key k", "estimator: {estimator} (every material's, where a scene of both lobe sets samples each "
                   "its own way)"},
    {"G", "key g", "G term: {gterm}"},
    {"V / shift+V", "key v|key shift+v", "view, forward / back: {views}"},
    {"T", "key t", "trace the pixel under the pointer (softlight trace's text, in the window and on stdout)"},
    {"M", "key m", "compare with the GL version: C -> GL -> C - GL difference -> C; once the frame is exact, "
                   "softlight-gl lights its G-buffer with the same camera and settings (--glsl: the GLSL twin of "
                   "--lighting) and the HUD shows the agreement"},
    {"PageUp / PageDown", "key PageUp|key PageDown", "page through the trace"},
    {"H", "key h", "HUD: full -> compact -> off -> full"},
    {"F12 or P", "key F12|key p", "screenshot: softlight-N.png and .hdr (N counts up past existing files)"},
    {"F1 or ?", "key F1|key shift+/", "this help"},
    {"Esc", "key Escape", "close the trace or the help, else quit"},
    {"drop a file", "drop PATH", ".hdr: new environment; .json: new scene; any other file: a model in the default scene"},
};

int view_keys_count(void) { return (int)(sizeof rows / sizeof rows[0]); }

/* "a -> b -> c -> a" from the option table's choices min .. max. */
static void option_cycle(const sl_option *opt, char *out, size_t size)
{
    size_t n = 0;
    out[0] = '\0';
    for (int v = (int)opt->min; v <= (int)opt->max + 1 && n < size; v++) {
        int w = v > (int)opt->max ? (int)opt->min : v;
        int k = snprintf(out + n, size - n, "%s%s", v > (int)opt->min ? " -> " : "", opt->names[w]);
        if (k < 0)
            return;
        n += (size_t)k;
    }
}

static void expand(const char *word, char *out, size_t size)
{
    out[0] = '\0';
    if (!strcmp(word, "lod")) {
        option_cycle(&sl_options[SL_OPT_LOD], out, size);
    } else if (!strcmp(word, "estimator")) {
        option_cycle(&sl_options[SL_OPT_ESTIMATOR], out, size);
    } else if (!strcmp(word, "gterm")) {
        option_cycle(&sl_options[SL_OPT_GTERM], out, size);
    } else if (!strcmp(word, "irradiance")) {
        size_t n = 0;
        for (int i = 0; i <= VIEW_IRRADIANCE_CYCLE && n < size; i++) {
            sl_irradiance_method m = view_irradiance_cycle[i % VIEW_IRRADIANCE_CYCLE];
            int k = snprintf(out + n, size - n, "%s%s%s", i ? " -> " : "", sl_irradiance_name(m),
                             m == SL_IRRADIANCE_MAP ? " (when the scene names one)" : "");
            if (k < 0)
                return;
            n += (size_t)k;
        }
    } else if (!strcmp(word, "views")) {
        size_t n = 0;
        for (int i = 0; i < VIEW_MODE_COUNT && n < size; i++) {
            int k = snprintf(out + n, size - n, "%s%s", i ? ", " : "", view_mode_name((view_mode)i));
            if (k < 0)
                return;
            n += (size_t)k;
        }
    }
}

void view_keys_action(int i, char *out, size_t size)
{
    const char *s = rows[i].action;
    size_t n = 0;
    while (*s && n + 1 < size) {
        const char *close = *s == '{' ? strchr(s, '}') : NULL;
        if (close) {
            char word[32], text[512];
            snprintf(word, sizeof word, "%.*s", (int)(close - s - 1), s + 1);
            expand(word, text, sizeof text);
            int k = snprintf(out + n, size - n, "%s", text);
            n = k < 0 ? n : n + (size_t)k;
            s = close + 1;
            continue;
        }
        out[n++] = *s++;
    }
    out[n < size ? n : size - 1] = '\0';
}

const char *view_keys_input(int i) { return rows[i].input; }
const char *view_keys_script(int i) { return rows[i].script; }

void view_keys_markdown(FILE *out)
{
    fprintf(out, "| input | action | script |\n|---|---|---|\n");
    for (int i = 0; i < view_keys_count(); i++) {
        char action[1024], script[256];
        view_keys_action(i, action, sizeof action);
        /* the script's commands as code, "|" (a cell separator in markdown) as " or " */
        size_t n = 0;
        script[0] = '\0';
        for (const char *s = rows[i].script; *s && n + 8 < sizeof script;) {
            size_t len = strcspn(s, "|");
            int k = snprintf(script + n, sizeof script - n, "%s`%.*s`", n ? " " : "", (int)len, s);
            n = k < 0 ? n : n + (size_t)k;
            s += len;
            if (*s == '|')
                s++;
        }
        fprintf(out, "| %s | %s | %s |\n", rows[i].input, action, script);
    }
}
