/* view_internal.h - the parts of `softlight view` shared between its files (not a public API;
 * only src/app/cmd_view.c and src/app/view_*.c include it). A file per job:
 *   cmd_view.c        the command: options, window and scene setup, the loop, acting on input
 *   view_refine.c     the refinement: which stage next (moving, accumulate, exact), rendering it
 *   view_present.c    the window: texture upload, the HUD, the help overlay, the message line
 *   view_texture.c    the window's streaming texture: sized, locked, unlocked
 *   view_screenshot.c screenshots (the exact frame as .png + .hdr) and the script's snapshots
 *   view_script.c     --script: reading it, and running it a turn of the loop at a time
 *   view_input.c      keys, mouse, window events and drops -> state changes and a view_action
 *   view_bench.c      --benchmark: a steady drag, timed from present to present
 *   view_camera.c     the orbit camera (Z-up world, orbit about +Z around the target)
 *   view_image.c      what the window shows: the tone-mapped frame, G-buffer channels, mip levels
 *   view_shade.c      the lighting pass in row slices (sl_lighting_shade_row)
 *   view_hud.c        text: the heads-up display and the help overlay (SDL2_ttf)
 *   view_keys.c       the key table: the help overlay, `--keys` (docs/viewer.md) and the script's names
 *   view_probe.c      the pixel under the pointer: its readout, and its trace (softlight trace's text)
 *   view_reload.c     the files a scene was loaded from, polled for changes
 *   view_program.c    --lighting, --gbuffer-shader: the user's programs, recompiled in the background
 *                     when its source changes, and swapped in between frames
 *   view_gl.c         M: the exact frame beside softlight-gl's lighting of its G-buffer, or their
 *                     difference
 * Which file calls which:
 *   cmd_view.c        -> every file below
 *   view_script.c     -> view_screenshot.c, view_refine.c, view_gl.c
 *   view_screenshot.c -> view_present.c, view_refine.c, view_image.c
 *   view_input.c      -> view_present.c (messages), view_camera.c, view_image.c, view_keys.c,
 *                        view_probe.c, view_reload.c
 *   view_bench.c      -> view_refine.c, view_camera.c, view_present.c, view_image.c
 *   view_present.c    -> view_refine.c (its questions, for the HUD), view_hud.c, view_image.c,
 *                        view_texture.c, view_keys.c, view_probe.c (the readout)
 *   view_probe.c      -> view_image.c, view_refine.c (its sizes and restarts)
 *   view_keys.c       -> view_image.c (the views' names)
 *   view_reload.c     -> nothing of the viewer's
 *   view_program.c    -> view_reload.c (the watch), view_refine.c (the restart)
 *   view_present.c    -> view_program.c (its HUD lines), view_gl.c (its HUD line)
 *   view_input.c      -> view_gl.c (M)
 *   view_gl.c         -> view_refine.c (its questions)
 *   view_refine.c     -> view_shade.c, view_image.c, view_texture.c
 *   view_texture.c    -> nothing of the viewer's (a failure goes back as an sl_error)
 * Every call goes one way.
 * Input does not restart the refinement or take screenshots itself: view_handle_event answers
 * a view_action, which the loop takes before the next event.
 * The camera, image and shade parts need no SDL; the others only exist when SL_HAVE_SDL2 is set
 * (the viewer state below names SDL's types only through pointers). */
#ifndef SL_VIEW_INTERNAL_H
#define SL_VIEW_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "core/error.h"
#include "core/image.h"
#include "render/renderer.h"
#include "scene/scene.h"

/* ---- view_camera.c ----
 * The scene's camera is the home position and is rendered exactly as given until the user moves;
 * the first move turns it into orbit form (target, distance, azimuth, elevation) with up = +Z,
 * elevation kept within +-VIEW_MAX_ELEVATION so the view never flips over the pole. */
#define VIEW_MAX_ELEVATION 89.0f

typedef struct {
    sl_camera home;   /* the scene's camera: reset returns to it exactly */
    sl_camera cam;    /* what is rendered (cmd_view.c and view_input.c) */
    bool at_home;     /* cam == home, bit for bit */
    vec3 target;
    float distance, azimuth_deg, elevation_deg;
    float home_distance;
    vec3 lo, hi;      /* the scene's bounds: zoom stays outside them, F frames them */
    bool have_bounds;
} view_camera;

void view_camera_init(view_camera *c, const sl_camera *home);
void view_camera_reset(view_camera *c);
/* Degrees about +Z (positive turns the eye counter-clockwise seen from above) and up/down. */
void view_camera_orbit(view_camera *c, float d_azimuth_deg, float d_elevation_deg);
/* Move target and eye in the image plane by fractions of the image height at the target's depth
 * (dx > 0: the scene follows the mouse to the right; dy > 0: the scene moves down). */
void view_camera_pan(view_camera *c, float dx, float dy);
/* Multiply the distance to the target (< 1 moves closer), held between the nearest distance
 * that keeps the eye outside the bounds (plus a margin) and 10 x the framing distance. */
void view_camera_zoom(view_camera *c, float factor);
/* After a reload: the old camera's orbit (target, distance, direction) in the new scene's
 * limits, unless it was at home. */
void view_camera_carry(view_camera *c, const view_camera *old);
/* The scene's bounds, for the zoom's limits and framing (call after init). */
void view_camera_set_bounds(view_camera *c, vec3 lo, vec3 hi);
/* Frame the bounds: target their centre, distance so the bounding sphere fits the view at this
 * aspect (width / height), direction kept. */
void view_camera_frame(view_camera *c, float aspect);
/* The framing distance of the bounds at this aspect (for tests of the limits). */
float view_camera_frame_distance(const view_camera *c, float aspect);

/* ---- view_image.c ---- */
typedef enum {
    VIEW_FINAL,    /* the tone-mapped frame */
    VIEW_POSITION, /* world position inside the scene's bounds, as RGB */
    VIEW_NORMAL,   /* normal * 0.5 + 0.5 */
    VIEW_KD,       /* diffuse albedo (gamma encoded for display) */
    VIEW_KS,       /* Schlick F0 (gamma encoded) */
    VIEW_ALPHA,    /* Phong exponent, log scale 0 .. 10000 */
    VIEW_DEPTH,    /* eye distance, near = white .. far = black over the covered pixels */
    VIEW_MIP,      /* mean mip level of the specular samples, false colour */
    VIEW_MODE_COUNT
} view_mode;

const char *view_mode_name(view_mode mode);
bool view_mode_needs_shading(view_mode mode); /* FINAL only */
bool view_mode_needs_lighting(view_mode mode); /* FINAL and MIP: the lighting uniforms */

/* Fill `out` (3 channels, the G-buffer's size, row 0 = top, values in [0,1]) with a G-buffer
 * channel view (POSITION .. DEPTH). `lo`/`hi`: the scene's bounds for POSITION; near/far of the
 * camera that rastered the G-buffer for DEPTH; `depth_range` (may be NULL) gets DEPTH's nearest
 * and farthest distance on screen, white and black (for the legend). */
bool view_channel_image(const sl_gbuffer *gb, view_mode mode, vec3 lo, vec3 hi, float znear, float zfar,
                        sl_image *out, float depth_range[2], sl_error *err);
/* The mean, over a traced pixel's specular samples above the horizon, of their mip levels (the
 * mip view's value and the readout's); NAN when no sample reached the environment. */
float view_trace_mean_level(const sl_lighting_trace *trace);
/* The mip-level view: per pixel, the mean over the samples above the horizon of the level that
 * lighting.frag's mip_level() gives them, run through the lighting shader's own trace (so it is
 * the same formula and the same samples); 0 = blue .. uEnvMaxLod = red, empty pixels black.
 * `max_level_seen` returns the largest per-pixel mean (for the HUD). Needs prepared uniforms. */
bool view_mip_image(const sl_lighting_uniforms *u, const sl_gbuffer *gb, sl_image *out, float *max_level_seen,
                    sl_error *err);
/* A 3-channel [0,1] image as SDL_PIXELFORMAT_XRGB8888 (one 32-bit word a pixel, what SDL's
 * renderers and X servers take without converting), each code rounded like the PNG writer
 * (v * 255 + 0.5). `pitch` in bytes, a multiple of 4 (SDL's locked textures are). */
void view_image_to_xrgb8888(const sl_image *img, uint8_t *pixels, int pitch);
/* What the window shows while `shown_pending` (a frame lit into r.radiance whose display image
 * goes straight into the window, view_present.c): the tone map of r.radiance made into `shown`
 * for the readers that need its values (screenshots, snapshots, the exact stage's rows), before
 * anything overwrites r.radiance. Nothing to do when not pending. */
typedef struct viewer viewer;
bool view_shown_make(viewer *v, sl_error *err);
/* The size of what the window shows (r.radiance's while pending, else `shown`'s; 0 x 0: none). */
void view_shown_size(const viewer *v, int *w, int *h);
/* `dst` gets `src`'s pixels: swapped when both have the same size (src then holds dst's old
 * pixels, a buffer of its size for the next tone map), else copied into dst (reallocated). */
bool view_image_take(sl_image *dst, sl_image *src, sl_error *err);

/* ---- view_shade.c ----
 * The lighting pass in slices of image rows, top first, so the viewer can handle input between
 * slices and show the rows already done. Rows go through sl_lighting_shade_row (the batched path
 * sl_lighting_pass runs), so the finished image is bit for bit the one `softlight render` makes. */
typedef struct {
    sl_lighting_task **tasks; /* one per thread, kept between jobs */
    int thread_count;
    int next_row;             /* next image row (row 0 = top) */
    double row_seconds;       /* measured cost of one row, to size the next slice */
    int last_rows;            /* rows in the last slice */
    double seconds;           /* spent on this job so far */
    int64_t nonfinite_base;   /* the tasks' NaN/Inf count when the job began */
    sl_lighting_planes planes; /* what the rows read from the whole G-buffer, filled when the job
                                  begins (as sl_lighting_pass fills its own) */
    /* When display is set, each row is also tone mapped into it (row y at display + y
     * display_pitch, sl_tonemap_row_xrgb8888) right after it is lit, while it is in cache:
     * a moving frame goes straight into the window's texture (view_refine.c). */
    const sl_tonemap_table *display_tab;
    uint8_t *display;
    int display_pitch;
} view_shade_job;

/* Start a job for freshly prepared uniforms u over gb (threads <= 0: OpenMP's default); rows are
 * shaded straight into the output image. `same_cost`: the last job's rows cost the same (the next
 * frame of an accumulation), so its measured row cost sizes the first slice; else it is measured
 * again. */
bool view_shade_begin(view_shade_job *job, const sl_lighting_uniforms *u, const sl_gbuffer *gb, int threads,
                      bool same_cost, sl_error *err);
/* Shade rows until about `budget_s` seconds have passed (at least two rows a thread; INFINITY:
 * every row left, in one parallel region). `first_row` gets the first row done by this call.
 * True when every row of `out` is done. */
bool view_shade_slice(view_shade_job *job, const sl_lighting_uniforms *u, const sl_gbuffer *gb, sl_image *out,
                      double budget_s, int *first_row);
void view_shade_free(view_shade_job *job);
/* Pixels of this job so far whose NaN/Inf the lighting stage replaced (a user's program's:
 * drawn magenta). */
int64_t view_shade_nonfinite(const view_shade_job *job);

/* ---- view_script.c: the script's commands (running it: below the viewer's state) ---- */
typedef enum {
    VIEW_CMD_WAIT,       /* wait MS: let MS milliseconds pass (frames keep running) */
    VIEW_CMD_SETTLE,     /* settle: wait until refinement has finished */
    VIEW_CMD_DRAG,       /* drag X0 Y0 X1 Y1 [left|right|middle] [STEPS] */
    VIEW_CMD_MOVE,       /* move X Y: mouse motion with no button */
    VIEW_CMD_WHEEL,      /* wheel N: N clicks (positive = away from the user = zoom in) */
    VIEW_CMD_KEY,        /* key [shift+|ctrl+]NAME: press and release (SDL key names) */
    VIEW_CMD_KEYDOWN,    /* keydown NAME: press and hold */
    VIEW_CMD_KEYUP,      /* keyup NAME */
    VIEW_CMD_RESIZE,     /* resize W H: set the window size (waits up to 2 s for it to apply) */
    VIEW_CMD_DROP,       /* drop PATH: a file dropped on the window */
    VIEW_CMD_SCREENSHOT, /* screenshot [NAME]: NAME.png + NAME.hdr, else softlight-<n> */
    VIEW_CMD_QUIT,       /* quit: as closing the window */
    VIEW_CMD_ACCUMULATED, /* accumulated K: wait until the still camera's mean holds K frames */
    VIEW_CMD_SNAPSHOT,   /* snapshot NAME: NAME.png + NAME.pfm of what is on screen now */
    VIEW_CMD_READOUT,    /* readout: print the readout of the pixel under the pointer */
} view_cmd_kind;

typedef struct {
    view_cmd_kind kind;
    int line;
    int args[6];
    int key;            /* SDL_Keycode */
    int mod;            /* SDL_Keymod */
    char text[SL_PATH_MAX];
} view_cmd;

typedef struct {
    view_cmd *cmds;
    int count;
    int next;
    double wait_until;  /* WAIT and RESIZE: seconds (sl_now_seconds) */
    bool waiting;       /* the command at `next` has started and not finished */
    int mouse_x, mouse_y; /* where the scripted pointer is, for MOVE's relative motion */
} view_script;

/* Parse a script file; errors name the file and line. Key names are checked here, so a script
 * fails before the window opens. (Needs SDL for the key names.) */
bool view_script_load(const char *path, view_script *s, sl_error *err);
void view_script_free(view_script *s);

/* ---- view_keys.c ----
 * One table of inputs: the help overlay shows it, `softlight view --keys` prints it as the
 * markdown table of docs/viewer.md, and its script column names the script's spelling. */
#define VIEW_IRRADIANCE_CYCLE 5
extern const sl_irradiance_method view_irradiance_cycle[VIEW_IRRADIANCE_CYCLE]; /* I's order */
int view_keys_count(void);
const char *view_keys_input(int i);
const char *view_keys_script(int i);
void view_keys_action(int i, char *out, size_t size); /* the action, cycles spelled out */
void view_keys_markdown(FILE *out);

/* ---- view_hud.c ---- */
#define VIEW_HUD_MAX_LINES 64
typedef struct view_hud view_hud;

/* NULL (and err) when the font cannot be opened: the viewer then runs without text. */
view_hud *view_hud_create(const char *font_path, int point_size, sl_error *err);
void view_hud_destroy(view_hud *hud);
/* Draw `count` lines in a translucent box at (x, y), or centred in the window when centre is
 * set; lines that did not change since the last call reuse their texture. `slot_base` picks a
 * separate cache for each block of lines (HUD, help). Returns the box height. */
struct SDL_Renderer;
int view_hud_draw(view_hud *hud, struct SDL_Renderer *sdl, int slot_base, const char *const *lines, int count, int x,
                  int y, bool centre);
/* Width in pixels of `text` in the HUD's font (0 when it cannot tell), and the line height. */
int view_hud_text_width(view_hud *hud, const char *text);
int view_hud_line_height(const view_hud *hud);

/* ---- the viewer's state ----
 * One struct, passed first to every function below. Each group of fields names the file that
 * owns it; the others read it, and ask for work through its flags (urgent, retonemap,
 * texture_stale, present_needed, quit). Input edits the user's settings: camera, r.desc, mode. */
#define VIEW_MAX_PREVIEW_DIV 8
#define VIEW_ORBIT_DEG_PER_PIXEL 0.4f /* a left drag turns the camera this much a pixel */

typedef struct {
    int div;         /* the render size is the window's (times --scale) divided by this */
    int samples;     /* N */
    bool rotate;     /* per-pixel rotation of the sample set (uRotate) */
    uint32_t frame;  /* its frame number (uFrame) */
    sl_estimator estimator; /* SL_ESTIMATOR_DEFAULT: the user's; moving frames: SPLITSUM */
} view_stage_params;

/* What the linear image behind `shown` is (for exposure changes and snapshots). */
typedef enum {
    VIEW_SHOWN_NONE,
    VIEW_SHOWN_RADIANCE, /* r.radiance */
    VIEW_SHOWN_MEAN,     /* the accumulation's mean */
    VIEW_SHOWN_GL,       /* softlight-gl's lighting of the exact frame's G-buffer (view_gl.c) */
    VIEW_SHOWN_DIFF,     /* the difference of the exact frame and that (view_gl.c) */
} view_shown_source;

/* The comparison with the GL version (view_gl.c): what M shows once the frame is exact. */
typedef enum { VIEW_GL_OFF, VIEW_GL_IMAGE, VIEW_GL_DIFF, VIEW_GL_MODES } view_gl_mode;
typedef struct {
    view_gl_mode mode;
    const char *glsl;       /* --glsl: the GLSL twin of --lighting (NULL: shaders/lighting.frag) */
    bool frame_changed;     /* set by view_refine.c's restarts: the GL image no longer fits */
    bool valid;             /* `radiance` is softlight-gl's lighting of the current exact frame */
    bool failed;            /* it failed for the current frame: not retried until the frame changes */
    sl_image c_radiance;    /* the exact frame it was compared with */
    sl_image radiance;      /* softlight-gl's */
    sl_image difference;    /* |C - GL| per channel, linear: what a snapshot of the difference writes */
    sl_tonemap_options shown_tonemap; /* the tone map `shown` was made with */
    double p99_rel, max_abs, over1, over8; /* sl_compare_images' figures, C as A */
    char renderer[96];      /* GL_RENDERER */
    double ms;              /* the last run's time */
} view_gl;

/* Navigation keys, tracked from events so a held key keeps the preview going (SDL's own keyboard
 * state does not see scripted events). */
enum {
    VIEW_NAV_LEFT, VIEW_NAV_RIGHT, VIEW_NAV_UP, VIEW_NAV_DOWN, VIEW_NAV_W, VIEW_NAV_A, VIEW_NAV_S, VIEW_NAV_D,
    VIEW_NAV_IN, VIEW_NAV_OUT, VIEW_NAV_COUNT
};

/* The files a scene was loaded from (the scene file, its meshes, models and images, its
 * environment and irradiance map) and their modification times, polled a few times a second. */
typedef struct {
    char (*paths)[SL_PATH_MAX];
    long long *mtimes; /* nanoseconds; -1: missing */
    int count;
    double next_poll;
} view_watch;

/* --lighting and --gbuffer-shader: the user's programs (view_program.c). Each compile runs on a
 * thread of its own; the loop polls it and swaps the result in between frames. */
typedef struct view_program_state view_program_state;
typedef enum { VIEW_PROGRAM_LIGHTING, VIEW_PROGRAM_GBUFFER, VIEW_PROGRAM_KINDS } view_program_kind;

/* --benchmark: per-frame times of the moving stage, from one present to the next. */
typedef struct {
    int frames;        /* to measure (0: no benchmark) */
    int done;          /* presented so far, warm-up included */
    double last_present;
    double *frame_ms, *raster_ms, *shade_ms, *tonemap_ms, *present_ms;
    int div_counts[VIEW_MAX_PREVIEW_DIV + 1];
    int last_w, last_h;
} view_bench;

struct viewer {
    /* window (cmd_view.c; view_present.c: the texture) */
    struct SDL_Window *window;
    struct SDL_Renderer *sdl;
    struct SDL_Texture *texture;
    int texture_w, texture_h;
    bool texture_stale; /* `shown` changed since the last upload */
    view_hud *hud;      /* NULL: no font, no text */
    bool show_hud, show_help;
    bool hud_compact;   /* H: full -> compact -> off */
    bool hud_chosen;    /* H was pressed: the window's size no longer picks full or compact */

    /* what is rendered (cmd_view.c and view_input.c) */
    sl_scene *scene;
    sl_renderer r;           /* r.desc: the user's settings (N, rotation, frame, toggles), which the
                                exact stage lights with; other stages override N, rotation and
                                frame per frame (sl_lighting_frame), never by writing r.desc */
    sl_render_desc cli_desc; /* the command line's settings, for scenes dropped later */
    vec3 bounds_lo, bounds_hi;
    view_camera camera;
    sl_lighting_options home_lighting; /* the settings the scene started with (and the command */
    sl_tonemap_options home_tonemap;   /* line's): R restores them */
    float home_ao_radius;              /* and the ambient occlusion's radius (0: off) */
    float ao_radius_on;                /* the radius O turns occlusion on with */
    bool home_shadows;                 /* every point light casting (--shadows): U toggles it */
    int home_sky_maps;                 /* the sky visibility maps (--sky-maps; 0: off) */
    int sky_maps_on;                   /* the count Y turns the sky maps on with */
    float home_reflection;             /* the reflection occlusion's distance (0: off) */
    float reflection_on;               /* the distance J turns it on with */
    char env_override[SL_PATH_MAX];    /* --env, `view FILE.hdr`'s or a dropped environment; "": the scene's */
    view_mode mode;
    int move_samples; /* N while moving (--move-samples) */
    bool move_user;   /* --move-estimator user: moving frames sample with the user's estimator
                         (N move_samples, rotated) instead of the split sum */
    bool acc_total_lod; /* accumulation frames filter as for the user's N (--accumulate-lod total) */
    int fixed_div;   /* --move-div; 0: adaptive */
    float scale;     /* --scale */
    bool irradiance_stale; /* the environment changed while the diffuse term was off */
    bool env_replaced;     /* a dropped .hdr replaced the scene's environment (its map no longer fits) */

    /* refinement (view_refine.c) */
    int stage;       /* next stage to render; VIEW_STAGE_COUNT: done */
    bool urgent;     /* something changed: render `stage` now, even during input */
    bool retonemap;  /* exposure/contrast changed: tone map and present only */
    int preview_div;
    double preview_ms; /* smoothed cost of a moving frame, present included */
    uint32_t move_frame; /* frame number of the next moving frame's rotation */
    int acc_count;   /* accumulation frames in `mean` */
    sl_image acc_frame; /* the accumulation frame being lit */
    sl_image mean;   /* their running mean */
    double acc_ms;   /* time spent on the accumulation so far */
    bool raster_valid; /* the G-buffer holds the current camera at its current size */
    view_shade_job shade; /* the lighting pass of the stage in progress */
    bool job_active;   /* a stage's lighting pass is under way */
    int job_stage;
    view_stage_params job_params;
    bool radiance_exact; /* r.radiance is the exact frame of the current state */
    view_stage_params shown_params;
    int shown_stage;
    view_shown_source shown_from;
    sl_image shown;  /* what the window shows, [0,1], row 0 = top (unless shown_pending) */
    bool shown_pending; /* the window shows the tone map of r.radiance, made in one pass into the
                           texture (view_present.c); `shown` is made from it only when a reader
                           needs it (view_shown_make): a moving frame's tone map and 8-bit
                           conversion were two passes over the frame */
    float mip_max_seen;
    float depth_range[2]; /* the depth view's white and black, world units along the view axis */
    double raster_ms, shade_ms, tonemap_ms, present_ms;
    double last_present;
    bool present_needed;

    /* input (view_input.c) */
    double last_input;
    int drag_button;
    bool held[VIEW_NAV_COUNT];
    int pointer_x, pointer_y; /* the pointer in window coordinates; -1: outside */

    /* the trace of a pixel (view_probe.c), shown a page at a time over the image */
    char *trace_text;
    int trace_lines, trace_page;
    bool show_trace;

    /* reloading (view_reload.c, polled by cmd_view.c) */
    view_watch watch;

    /* the comparison with softlight-gl (view_gl.c) */
    view_gl gl;

    /* the lighting and G-buffer programs (view_program.c, by view_program_kind; NULL: the built-in) */
    view_program_state *programs[VIEW_PROGRAM_KINDS];
    int64_t shown_nonfinite; /* NaN/Inf pixels of the last frame lit in full (view_refine.c) */
    bool frame_lit;          /* a frame was lit in full since the last present (view_refine.c) */

    /* messages (view_present.c), script, counters */
    char message[256];
    double message_until;
    bool message_shown;
    view_script script;
    bool have_script;
    view_bench bench;
    long frames, max_frames;
    int shot_counter;
    int exit_status;
    bool quit;
};

/* ---- view_refine.c ----
 * Stages in order; `stage` is the next one to render, VIEW_STAGE_COUNT when done. */
enum { VIEW_STAGE_MOVING, VIEW_STAGE_ACCUMULATE, VIEW_STAGE_EXACT, VIEW_STAGE_COUNT };
#define VIEW_ACC_SAMPLES 8      /* N of one accumulation frame */
#define VIEW_QUIET_SECONDS 0.15 /* input this recent still counts as "moving" */

/* The camera, the scene or the window size changed: start again from the moving stage. */
void view_restart_camera(viewer *v);
/* Lighting settings or the view mode changed: the G-buffer stays, the accumulation restarts. */
void view_restart_lighting(viewer *v);
/* Questions: the frames the current view accumulates (0: none); nothing left to render; input
 * is in progress (a drag, a held key, input in the last VIEW_QUIET_SECONDS, a benchmark). */
int view_acc_target(const viewer *v);
bool view_converged(const viewer *v);
bool view_interacting(const viewer *v, double now);
/* The window's size in pixels, and the render size for a divisor (times --scale, clamped). */
void view_output_size(const viewer *v, int *w, int *h);
void view_render_size(const viewer *v, int div, int *w, int *h);
/* For the loop, one at a time: a stage is due (not during input unless urgent, not minimized);
 * start it (a moving frame whole, later stages' first step); continue the active stage by one
 * slice of about 40 ms; after a moving frame was presented, advance its frame number and adapt
 * the preview divisor to its cost (`frame_ms`, present included). False: a render failed (err). */
bool view_refine_wanted(const viewer *v, double now);
bool view_refine_start(viewer *v, sl_error *err);
bool view_refine_continue(viewer *v, sl_error *err);
void view_refine_moved(viewer *v, double frame_ms);
/* After a failure: stop refining until the next restart (retrying would fail the same way). */
void view_refine_stop(viewer *v);
/* Render the exact frame now, whatever stage was next (a screenshot needs it). */
bool view_refine_finish(viewer *v, sl_error *err);
/* Exposure or contrast changed: tone map the linear image behind `shown` again. */
bool view_refine_retonemap(viewer *v, sl_error *err);

/* ---- view_present.c ---- */
/* Draw `shown`, the HUD or the help, and present; counts frames (--frames quits). */
void view_present(viewer *v);
/* One line in the HUD for a few seconds; errors also go to stderr (the window may be hidden). */
void view_message(viewer *v, bool error, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
const char *view_irradiance_name(sl_irradiance_method m); /* "sh9", "brute", "map" */
/* How a stage lit its frame, for the HUD, snapshots and the benchmark: "split sum" or
 * "N 8 rotated" (view_present.c). */
void view_stage_describe(const view_stage_params *s, char *buf, size_t size);

/* ---- view_texture.c ---- */
/* Lock the window's texture at w x h (recreated when its size differs) for writing: its pixels
 * (XRGB8888 words) and pitch. False, with err, when SDL cannot; the caller reports it. */
bool view_texture_lock(viewer *v, int w, int h, uint8_t **pixels, int *pitch, sl_error *err);
void view_texture_unlock(viewer *v);

/* ---- view_screenshot.c ---- */
/* The exact frame of the current view as <name>.png (what is shown, without the HUD) and
 * <name>.hdr (linear radiance); softlight-<n> when name is NULL or empty. The refinement is
 * completed first, so the files are full size, full N whatever the window showed. */
bool view_screenshot(viewer *v, const char *name, sl_error *err);
/* What is on screen now, without completing the refinement (the script's `snapshot`, for tests
 * of the stages themselves): <base>.png as shown and <base>.pfm, the linear image behind it (the
 * accumulated mean, or the moving or exact frame). */
bool view_snapshot(viewer *v, const char *base, sl_error *err);

/* ---- view_script.c: running ---- */
/* Run the script commands that are due (one turn of the loop, before its events are handled). */
void view_script_step(viewer *v, double now);

/* ---- view_bench.c ---- */
bool view_bench_init(view_bench *b, int frames, sl_error *err);
void view_bench_free(view_bench *b);
/* Input for the next benchmark frame: what a mouse drag of a few pixels does. */
void view_bench_input(viewer *v, double now);
/* A moving frame was presented at `now`: record it; after the last, report and quit. */
void view_bench_record(viewer *v, double now);

/* ---- view_input.c ---- */
/* What an event asks of the loop beyond the state it changed. */
typedef enum {
    VIEW_ACT_NONE,
    VIEW_ACT_RESTART_CAMERA,   /* the camera, the scene or the window size changed */
    VIEW_ACT_RESTART_LIGHTING, /* lighting settings, the environment or the view mode changed */
    VIEW_ACT_SCREENSHOT,       /* F12 or P: softlight-<n>.png and .hdr */
} view_action;

/* Take over a loaded scene and its renderer (the old ones are freed) and reset the camera to the
 * scene's; the caller restarts the refinement. */
void view_adopt_scene(viewer *v, sl_scene *scene, const sl_renderer *r);
union SDL_Event;
view_action view_handle_event(viewer *v, union SDL_Event *e);
/* Read a scene file (a model, the default scene around it) and, with `env`, put that
 * environment in place of the scene's as render's --env does (relative to here, no irradiance
 * map); the scene's warnings go to stderr. */
bool view_is_environment(const char *path); /* .hdr, .exr or .pfm */
bool view_read_scene(const char *path, const char *env, const sl_option_values *given, sl_scene **out, sl_error *err);
/* Load a scene file (a model, or with v->env_override its environment in place of the
 * scene's) and build its renderer at the current size with the command line's options. */
bool view_load_scene(viewer *v, const char *path, sl_error *err);
/* R: every setting back to what the scene started with; the caller restarts the camera. */
void view_reset_all(viewer *v);

/* ---- view_probe.c ---- */
/* The pixel under the pointer (window coordinates) in an image of w x h shown over the window;
 * false when the pointer is outside. */
bool view_pointer_pixel(const viewer *v, int w, int h, int *x, int *y);
/* The readout of the pixel under the pointer: its radiance in the final view, its value and
 * unit in a G-buffer view, its mean level in the mip view. `digits`: significant digits (4 for
 * the HUD, 9 for the script's `readout`). False (and buf "") when the pointer is outside. */
bool view_readout(viewer *v, int digits, char *buf, size_t size);
/* Trace the full-size pixel under the pointer as `softlight trace --pixel X,Y` does (a raster
 * with the fetch hook, the exact frame's uniforms, the lighting shader's trace) into
 * v->trace_text, shown in the window and printed on stdout. */
bool view_trace_pointer(viewer *v, sl_error *err);
void view_trace_free(viewer *v);

/* ---- view_reload.c ---- */
/* Record the files of `scene` (and `env_override`, if set) and their times. */
bool view_watch_scene(view_watch *w, const sl_scene *scene, const char *env_override, sl_error *err);
/* True (at most every VIEW_POLL_SECONDS) when a watched file's time changed since it was recorded. */
#define VIEW_POLL_SECONDS 0.25
bool view_watch_changed(view_watch *w, double now);
void view_watch_free(view_watch *w);
/* Watch one file alone (what was watched before is dropped). */
bool view_watch_file(view_watch *w, const char *path, sl_error *err);

/* ---- view_gl.c ----
 * M cycles C -> GL -> C - GL difference -> C. Once the frame is exact (view_converged, the final
 * view), softlight-gl lights the exact frame's G-buffer from the viewer's camera with the same
 * settings (gl_twin.h), and the window shows its image or the difference; any change of camera
 * or lighting starts the refinement again, and the comparison follows it. */
/* M: the next mode; `what` gets the message that says what it shows. */
void view_gl_cycle(viewer *v, char *what, size_t size);
/* The loop's questions: is there GL work to do or an image to switch to now, and does that work
 * run softlight-gl (the loop says so on screen first)? */
bool view_gl_wanted(const viewer *v);
bool view_gl_will_run(const viewer *v);
/* Do it: run softlight-gl when the exact frame has no GL image yet (blocking: seconds on llvmpipe
 * at 1280x720, docs/viewer.md), then show the mode's image. False and err when it failed (not retried
 * for this frame; the C frame stays on screen). */
bool view_gl_step(viewer *v, sl_error *err);
/* The HUD's line ("" when the mode is off). */
void view_gl_hud(const viewer *v, char *buf, size_t size);
void view_gl_free(viewer *v);

/* ---- view_program.c ---- */
/* Load `path` as a program of `kind` now (at startup: a failure is the command's error, with msg)
 * and watch it. */
bool view_program_open(viewer *v, view_program_kind kind, const char *path, bool debug, bool verbose, char *msg,
                       size_t msg_size);
/* Once a turn, for each program: start a compile when the source changed, swap a finished one in
 * (a lighting program restarts the lighting, a G-buffer program the raster), or report its error
 * (the last good program keeps running); once the first frame lit in full with a new program was
 * presented, print the time from the source's save to it. */
void view_program_poll(viewer *v, double now);
/* HUD lines: each program, its error, the NaN/Inf count (buf: lines separated by '\n'). */
void view_program_hud(const viewer *v, bool compact, char *buf, size_t size);
/* Seconds until the next poll is due (for the idle wait); a large value when nothing is watched. */
double view_program_wake(const viewer *v, double now);
void view_program_close(viewer *v);

#endif
