/* xrad view SCENE: the real-time loop in a window (GLFW), on the public API
 * alone (include/xrad_vulkan.h): redistribution runs on the scheduler's
 * thread, display here through xrad's viewer; an overlay on the image
 * shows both rates, the pass times, the method and the keys. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "cli.h"
#include "method.h"
#include "xrad_vulkan.h"

/* The little vector algebra the camera and the grab need. */
typedef struct vec3 {
    double x, y, z;
} vec3;

static vec3 v3(double x, double y, double z) { return (vec3){x, y, z}; }
static vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static vec3 v3_scale(vec3 a, double k) { return v3(a.x * k, a.y * k, a.z * k); }
static double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static vec3 v3_norm(vec3 a)
{
    double l = sqrt(v3_dot(a, a));
    return l > 0 ? v3_scale(a, 1 / l) : a;
}
static vec3 v3_from(const double *d) { return v3(d[0], d[1], d[2]); }
static void v3_to(vec3 a, double *d)
{
    d[0] = a.x;
    d[1] = a.y;
    d[2] = a.z;
}

/* The free camera: position, look_at, up (m, world), vertical field of view. */
typedef struct camera {
    vec3 position, look_at, up;
    double fov_y; /* radians */
} camera;

#define VIEW_MAX_OBJECTS 64

static void help(void)
{
    printf("usage: xrad view SCENE.json [options]\n\n"
           "Shows the scene in a window while its dynamic objects move: redistribution\n"
           "(thesis 4.5) runs on its own thread and the window shows the newest complete\n"
           "solution (two atlases, swapped at timeline values; thesis 4.5.3).\n\n"
           "  --method NAME     progressive (solve anew each frame), incremental or cross\n"
           "                    [cross]; switch at run time with 1 2 3\n"
           "  --time T          scene time to start at [0]\n"
           "  --fps F           scene frames per second of --frames and N [30]\n"
           "  --speed S         animation speed, scene seconds per second [1]\n"
           "  --width N, --height N   window size [the scene camera's, else 960 x 720]\n"
           "  --exposure E      display scale factor; 0 = auto from the first solution [0]\n"
           "  --tonemap T       exposure or reinhard (as xrad render's; T switches) [exposure]\n"
           "  --nearest         show elements as flat squares\n"
           "  --no-vsync        present without waiting for the display's refresh\n"
           "  --no-overlay      start without the figures on screen (H shows them)\n"
           "  --screenshot FILE with --frames: save the last frame (.png tone-mapped as shown,\n"
           "                    .exr linear) and exit\n"
           "  --frames N        show N frames, frame k at scene time T + k / F, the last one\n"
           "                    once its redistribution is complete, then exit\n"
           "  --resize-at N     (tests) resize the window at frame N to --resize-to\n"
           "  --resize-to WxH   [half the window]\n"
           "  --device NAME     Vulkan device (substring; see xrad devices)\n");
    method_print_options();
    printf("  (view's defaults: --slice 512 --batch 4, so that display frames get in\n"
           "  between redistribution submissions)\n\n"
           "Press ? or F1 in the window for the keys. Exit status 2 when there is no\n"
           "display or the device cannot present to it.\n");
}

static const char keys_text[] =
    "  left mouse drag        look around\n"
    "  W A S D, Q E           move forward, left, back, right; down, up\n"
    "  mouse wheel            movement speed up / down\n"
    "  Space                  pause / resume the animation\n"
    "  N                      one frame forward (1/fps) while paused\n"
    "  1 2 3                  method: progressive (restart), incremental, cross\n"
    "  G                      grab the next dynamic object (after the last: release)\n"
    "  arrows, PgUp PgDn      move the grabbed object: on the ground, down, up\n"
    "  + -                    exposure up / down\n"
    "  T                      tone mapping: exposure / Reinhard (exposure measured anew)\n"
    "  V                      elements (nearest) / interpolated\n"
    "  R                      camera back to the scene's\n"
    "  F2                     screenshot to out/view-NNNN.png\n"
    "  H                      overlay off / on\n"
    "  ? F1                   this list, on screen and on stdout\n"
    "  Esc                    quit\n";

static void keymap(void)
{
    printf("xrad view keys:\n%s", keys_text);
    fflush(stdout);
}

typedef struct view_opts {
    const char *scene, *method, *device, *screenshot;
    double time, fps, speed, exposure;
    xrad_tonemap tonemap;
    uint32_t width, height, frames, resize_at, resize_w, resize_h;
    int nearest, no_vsync, no_overlay;
    method_settings m;
} view_opts;

static int parse(int argc, char **argv, view_opts *o)
{
    cli_args a;
    cli_init(&a, argc, argv);
    const char *opt;
    o->method = "cross";
    o->fps = 30;
    o->speed = 1;
    /* Redistribution in slices and small progressive batches: on a device
     * with one queue (lavapipe) display frames get in between them. */
    o->m.solver.slice_elements = 512;
    o->m.override_name[0] = "batch";
    o->m.override_value[0] = "4";
    o->m.override_count = 1;
    while ((opt = cli_next(&a)) && !a.failed) {
        if (cli_is_help(opt)) {
            help();
            return -1;
        } else if (!strcmp(opt, "method")) {
            o->method = cli_value(&a);
        } else if (!strcmp(opt, "time")) {
            cli_double(&a, -1e6, 1e6, &o->time);
        } else if (!strcmp(opt, "fps")) {
            cli_double(&a, 1e-3, 1e6, &o->fps);
        } else if (!strcmp(opt, "speed")) {
            cli_double(&a, 0, 1e6, &o->speed);
        } else if (!strcmp(opt, "exposure")) {
            cli_double(&a, 0, 1e12, &o->exposure);
        } else if (!strcmp(opt, "tonemap")) {
            method_tonemap_option(&a, &o->tonemap);
        } else if (!strcmp(opt, "width")) {
            cli_uint(&a, 16, 16384, &o->width);
        } else if (!strcmp(opt, "height")) {
            cli_uint(&a, 16, 16384, &o->height);
        } else if (!strcmp(opt, "frames")) {
            cli_uint(&a, 1, 100000000, &o->frames);
        } else if (!strcmp(opt, "screenshot")) {
            o->screenshot = cli_value(&a);
        } else if (!strcmp(opt, "resize-at")) {
            cli_uint(&a, 1, 100000000, &o->resize_at);
        } else if (!strcmp(opt, "resize-to")) {
            const char *v = cli_value(&a);
            if (v && sscanf(v, "%ux%u", &o->resize_w, &o->resize_h) != 2)
                return cli_usage_error("view", "--resize-to: '%s' is not WxH", v);
        } else if (!strcmp(opt, "nearest")) {
            o->nearest = 1;
        } else if (!strcmp(opt, "no-vsync")) {
            o->no_vsync = 1;
        } else if (!strcmp(opt, "no-overlay")) {
            o->no_overlay = 1;
        } else if (!strcmp(opt, "device")) {
            o->device = cli_value(&a);
        } else if (!method_solver_option(&a, opt, &o->m)) {
            cli_unknown(&a, opt);
        }
    }
    if (a.failed)
        return 1;
    if (a.positional_count != 1)
        return cli_usage_error("view", "expected one scene file, got %d", a.positional_count);
    o->scene = a.positional[0];
    xrad_method m = xrad_method_from_name(o->method);
    if (m != XRAD_METHOD_PROGRESSIVE && m != XRAD_METHOD_INCREMENTAL && m != XRAD_METHOD_CROSS)
        return cli_usage_error("view", "--method: '%s' is not progressive, incremental or cross",
                               o->method);
    o->m.solver.method = m;
    if (o->screenshot && !o->frames)
        return cli_usage_error("view", "--screenshot needs --frames N");
    if (o->screenshot && !cli_has_ext(o->screenshot, ".png") &&
        !cli_has_ext(o->screenshot, ".exr"))
        return cli_usage_error("view", "--screenshot: '%s' is neither .png nor .exr",
                               o->screenshot);
    return 0;
}

/* ---------------------------------------------------------- input state */

typedef struct view_state {
    GLFWwindow *window;
    xrad_scene *scene; /* the display's copy */
    camera home, cam;
    double move_speed; /* m/s */
    double exposure;   /* 0: automatic (the viewer's) */
    xrad_tonemap tonemap;
    bool paused, step, nearest, screenshot_key;
    bool overlay, overlay_keys; /* figures on screen; the key list with them */
    xrad_method method;
    int grabbed;       /* object index, -1: none */
    double offsets[VIEW_MAX_OBJECTS][3];
    bool moved[VIEW_MAX_OBJECTS]; /* grabbed once: its pose goes with every request */
    bool dragging;
    double drag_x, drag_y;
    double diameter;   /* m, the scene's bounding box diagonal */
} view_state;

static vec3 cam_forward(const camera *c)
{
    return v3_norm(v3_sub(c->look_at, c->position));
}

/* Turns the camera by yaw about its up vector and pitch about its right. */
static void cam_turn(camera *c, double yaw, double pitch)
{
    vec3 f = cam_forward(c), up = v3_norm(c->up);
    vec3 right = v3_norm(v3_cross(f, up));
    vec3 f1 = v3_add(v3_scale(f, cos(yaw)), v3_scale(right, -sin(yaw)));
    vec3 f2 = v3_add(v3_scale(f1, cos(pitch)), v3_scale(up, sin(pitch)));
    /* Not over the pole: the view would flip. */
    if (fabs(v3_dot(v3_norm(f2), up)) < 0.995)
        f1 = f2;
    c->look_at = v3_add(c->position, v3_norm(f1));
}

static void grab_next(view_state *st)
{
    xrad_scene_info info;
    xrad_scene_get_info(st->scene, &info);
    for (uint32_t k = 1; k <= info.objects; k++) {
        int i = st->grabbed + (int)k;
        if (i >= (int)info.objects)
            break;
        xrad_object_info oi;
        if (!xrad_scene_get_object(st->scene, (uint32_t)i, &oi, NULL) && oi.dynamic &&
            i < VIEW_MAX_OBJECTS) {
            st->grabbed = i;
            printf("grabbed '%s' (arrows, PgUp/PgDn move it; G: next)\n", oi.name);
            fflush(stdout);
            return;
        }
    }
    if (st->grabbed >= 0)
        printf("released\n");
    else
        printf("the scene has no dynamic object to grab\n");
    fflush(stdout);
    st->grabbed = -1;
}

/* ? and F1: the key list on screen (again: off) and on stdout. */
static void show_keys(view_state *st)
{
    st->overlay_keys = !st->overlay_keys;
    st->overlay |= st->overlay_keys;
    keymap();
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    view_state *st = glfwGetWindowUserPointer(w);
    if (action != GLFW_PRESS)
        return;
    switch (key) {
    case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
    case GLFW_KEY_SPACE: st->paused = !st->paused; break;
    case GLFW_KEY_N: st->step = true; break;
    case GLFW_KEY_1: st->method = XRAD_METHOD_PROGRESSIVE; break;
    case GLFW_KEY_2: st->method = XRAD_METHOD_INCREMENTAL; break;
    case GLFW_KEY_3: st->method = XRAD_METHOD_CROSS; break;
    case GLFW_KEY_G: grab_next(st); break;
    case GLFW_KEY_V: st->nearest = !st->nearest; break;
    case GLFW_KEY_R: st->cam = st->home; break;
    case GLFW_KEY_F1: show_keys(st); break;
    case GLFW_KEY_H: st->overlay = !st->overlay; break;
    case GLFW_KEY_T:
        st->tonemap = st->tonemap == XRAD_TONEMAP_REINHARD ? XRAD_TONEMAP_EXPOSURE
                                                           : XRAD_TONEMAP_REINHARD;
        st->exposure = 0; /* the new operator's own, measured by the viewer */
        break;
    case GLFW_KEY_F2: st->screenshot_key = true; break;
    case GLFW_KEY_KP_ADD: st->exposure *= 1.25; break;
    case GLFW_KEY_KP_SUBTRACT: st->exposure /= 1.25; break;
    default: break;
    }
}

/* Characters, so that '?', '+' and '-' work on any keyboard layout. */
static void on_char(GLFWwindow *w, unsigned int c)
{
    view_state *st = glfwGetWindowUserPointer(w);
    if (c == '?')
        show_keys(st);
    else if (c == '+' || c == '=')
        st->exposure *= 1.25;
    else if (c == '-')
        st->exposure /= 1.25;
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)mods;
    view_state *st = glfwGetWindowUserPointer(w);
    if (button != GLFW_MOUSE_BUTTON_LEFT)
        return;
    st->dragging = action == GLFW_PRESS;
    glfwGetCursorPos(w, &st->drag_x, &st->drag_y);
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    view_state *st = glfwGetWindowUserPointer(w);
    if (!st->dragging)
        return;
    double k = st->cam.fov_y / 600.0; /* radians per pixel */
    cam_turn(&st->cam, (x - st->drag_x) * k, -(y - st->drag_y) * k);
    st->drag_x = x;
    st->drag_y = y;
}

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)dx;
    view_state *st = glfwGetWindowUserPointer(w);
    st->move_speed *= pow(1.25, dy);
}

static bool held(GLFWwindow *w, int key)
{
    return glfwGetKey(w, key) == GLFW_PRESS;
}

/* Held keys: the camera flies, the grabbed object moves. */
static void poll_motion(view_state *st, double dt)
{
    GLFWwindow *w = st->window;
    camera *c = &st->cam;
    vec3 f = cam_forward(c), up = v3_norm(c->up), right = v3_norm(v3_cross(f, up));
    vec3 d = v3(0, 0, 0);
    d = v3_add(d, v3_scale(f, held(w, GLFW_KEY_W) - held(w, GLFW_KEY_S)));
    d = v3_add(d, v3_scale(right, held(w, GLFW_KEY_D) - held(w, GLFW_KEY_A)));
    d = v3_add(d, v3_scale(up, held(w, GLFW_KEY_E) - held(w, GLFW_KEY_Q)));
    d = v3_scale(d, st->move_speed * dt);
    c->position = v3_add(c->position, d);
    c->look_at = v3_add(c->look_at, d);
    if (st->grabbed < 0)
        return;
    /* On the ground: forward and right without their up part. */
    vec3 gf = v3_norm(v3_sub(f, v3_scale(up, v3_dot(f, up))));
    vec3 gr = v3_norm(v3_cross(gf, up));
    vec3 m = v3(0, 0, 0);
    m = v3_add(m, v3_scale(gf, held(w, GLFW_KEY_UP) - held(w, GLFW_KEY_DOWN)));
    m = v3_add(m, v3_scale(gr, held(w, GLFW_KEY_RIGHT) - held(w, GLFW_KEY_LEFT)));
    m = v3_add(m, v3_scale(up, held(w, GLFW_KEY_PAGE_UP) - held(w, GLFW_KEY_PAGE_DOWN)));
    m = v3_scale(m, 0.25 * st->move_speed * dt);
    double *o = st->offsets[st->grabbed];
    o[0] += m.x;
    o[1] += m.y;
    o[2] += m.z;
    st->moved[st->grabbed] = true;
    xrad_error err;
    xrad_scene_set_offset(st->scene, (uint32_t)st->grabbed, o, &err);
}

/* -------------------------------------------------------------- overlay */

/* `passes` as "name ms" joined, largest first, `per_line` a line, each
 * line after the first indented. */
static size_t pass_lines(const xrad_pass_time *passes, uint32_t count, int per_line, char *out,
                         size_t size)
{
    bool used[XRAD_MAX_PASSES] = {0};
    size_t len = 0;
    out[0] = 0;
    for (uint32_t k = 0; k < count; k++) {
        int best = -1;
        for (uint32_t i = 0; i < count; i++)
            if (!used[i] && (best < 0 || passes[i].ms > passes[best].ms))
                best = (int)i;
        used[best] = true;
        const char *sep = !k ? "" : k % (uint32_t)per_line ? ", " : "\n    ";
        len += (size_t)snprintf(out + len, len < size ? size - len : 0, "%s%s %.1f", sep,
                                passes[best].name, passes[best].ms);
    }
    return len;
}

/* What the overlay shows: the scene and method, display and redistribution
 * rates, every pass's GPU ms (sliding means), and the keys when asked. */
static void overlay_text(const view_state *st, const char *name, xrad_scheduler *sch,
                         xrad_viewer *vw, char *out, size_t size)
{
    xrad_scheduler_stats ss;
    xrad_viewer_stats vs;
    xrad_scheduler_get_stats(sch, &ss);
    xrad_viewer_get_stats(vw, &vs);
    char solver[1024], display[256];
    pass_lines(ss.passes, ss.pass_count, 4, solver, sizeof(solver));
    pass_lines(vs.passes, vs.pass_count, 4, display, sizeof(display));
    snprintf(out, size,
             "%s   method %s%s   %s x %.3g\n"
             "display %.1f fps (%.1f ms a frame)\n"
             "redistribution %.0f ms (%s), solution at t = %.2f s\n"
             "GPU ms, redistribution:\n    %s\n"
             "GPU ms, display:\n    %s\n"
             "%s",
             name, xrad_method_name(st->method), st->paused ? "   paused" : "",
             xrad_tonemap_name(vs.tonemap), vs.exposure,
             vs.frame_ms > 0 ? 1000.0 / vs.frame_ms : 0.0, vs.frame_ms, ss.frame_ms,
             ss.published ? "running" : "first solve", vs.solution_time,
             ss.pass_count ? solver : "(none yet)", vs.pass_count ? display : "(none yet)",
             st->overlay_keys ? keys_text : "H: overlay off   ?: keys\n");
}

static void print_summary(xrad_scheduler *sch, xrad_viewer *vw)
{
    xrad_scheduler_stats ss;
    xrad_viewer_stats vs;
    xrad_scheduler_get_stats(sch, &ss);
    xrad_viewer_get_stats(vw, &vs);
    double frame = vs.frame_ms;
    printf("view: %llu frames, display %.1f fps (%.2f ms a frame), %llu redistributions, "
           "%.1f ms each with their progressive iterations, %.1f ms the redistribution "
           "alone (means of the last 32)\n",
           (unsigned long long)vs.frames, frame > 0 ? 1000.0 / frame : 0.0, frame,
           (unsigned long long)ss.published, ss.frame_ms, ss.redistribute_ms);
    printf("  GPU ms per pass (sliding means):\n");
    for (uint32_t i = 0; i < ss.pass_count; i++)
        printf("    %-24s %9.2f  (redistribution)\n", ss.passes[i].name, ss.passes[i].ms);
    for (uint32_t i = 0; i < vs.pass_count; i++)
        printf("    %-24s %9.2f  (display frame)\n", vs.passes[i].name, vs.passes[i].ms);
    printf("  swapchain recreations: %u, exposure %.4g (%s)\n", vs.recreations, vs.exposure,
           xrad_tonemap_name(vs.tonemap));
}

/* ---------------------------------------------------------------- loop */

static char glfw_message[512];

static void on_glfw_error(int code, const char *message)
{
    snprintf(glfw_message, sizeof(glfw_message), "%s (GLFW error 0x%x)", message, code);
}

/* The request of this frame: time, method, and the pose of every object
 * grabbed so far (its animation at `time` plus its offset, from the
 * display's copy of the scene). */
typedef struct view_request {
    double time;
    xrad_method method;
    uint32_t pose_count;
    xrad_object_pose poses[VIEW_MAX_OBJECTS];
} view_request;

static void make_request(const view_state *st, double time, view_request *r)
{
    memset(r, 0, sizeof(*r)); /* padding too: requests are compared bytewise */
    r->time = time;
    r->method = st->method;
    for (uint32_t i = 0; i < VIEW_MAX_OBJECTS; i++) {
        if (!st->moved[i])
            continue;
        xrad_object_pose *p = &r->poses[r->pose_count++];
        p->object = i;
        xrad_scene_get_object_pose(st->scene, i, time, p->matrix, NULL);
    }
}

static xrad_status run(const view_opts *o, view_state *st, xrad_scheduler *sch, xrad_viewer *vw,
                       xrad_error *err)
{
    char name[128];
    cli_basename_noext(o->scene, name, sizeof(name));
    double anim = o->time, last = glfwGetTime(), last_text = -1;
    char text[4096] = "";
    view_request req;
    memset(&req, 0, sizeof(req));
    uint64_t requests = 0, serial = 0;
    uint32_t shots = 0;
    xrad_status s = XRAD_OK;
    for (uint32_t frame = 1; !glfwWindowShouldClose(st->window); frame++) {
        glfwPollEvents();
        double now = glfwGetTime(), dt = now - last;
        last = now;
        poll_motion(st, dt);
        if (o->frames) {
            anim = o->time + frame / o->fps;
        } else if (!st->paused) {
            anim += dt * o->speed;
        } else if (st->step) {
            anim += 1.0 / o->fps;
        }
        st->step = false;
        if (o->resize_at && frame == o->resize_at) {
            int w, h;
            glfwGetFramebufferSize(st->window, &w, &h);
            glfwSetWindowSize(st->window, o->resize_w ? (int)o->resize_w : w / 2,
                              o->resize_h ? (int)o->resize_h : h / 2);
        }

        /* A request when the pose or the method changed. */
        view_request r;
        make_request(st, anim, &r);
        if (!requests || memcmp(&r, &req, sizeof(r))) {
            xrad_request q = {.time = r.time,
                              .method = r.method,
                              .poses = r.poses,
                              .pose_count = r.pose_count};
            if ((s = xrad_scheduler_request(sch, &q, &serial, err)))
                return s;
            req = r;
            requests++;
        }
        bool last_frame = o->frames && frame >= o->frames;
        if (last_frame && (s = xrad_scheduler_wait(sch, serial, err)))
            return s;

        char shot[64];
        const char *screenshot = NULL;
        if (last_frame && o->screenshot) {
            screenshot = o->screenshot;
        } else if (st->screenshot_key) {
            snprintf(shot, sizeof(shot), "out/view-%04u.png", shots++);
            cli_make_parent_dirs(shot);
            screenshot = shot;
            printf("screenshot %s\n", shot);
            fflush(stdout);
        }
        st->screenshot_key = false;
        /* Twice a second: figures that change every frame cannot be read. */
        if (st->overlay && now - last_text > 0.5) {
            overlay_text(st, name, sch, vw, text, sizeof(text));
            last_text = now;
        }
        int fw, fh;
        glfwGetFramebufferSize(st->window, &fw, &fh);
        xrad_viewer_frame_desc d = {
            .time = anim,
            .exposure = st->exposure,
            .tonemap = st->tonemap,
            .nearest = st->nearest,
            .width = (uint32_t)fw,
            .height = (uint32_t)fh,
            .screenshot = screenshot,
            .overlay = st->overlay ? text : NULL,
        };
        v3_to(st->cam.position, d.camera.position);
        v3_to(st->cam.look_at, d.camera.look_at);
        v3_to(st->cam.up, d.camera.up);
        d.camera.fov_degrees = st->cam.fov_y * 180.0 / M_PI;
        if ((s = xrad_viewer_frame(vw, sch, &d, err)))
            return s;
        if (st->exposure <= 0) {
            xrad_viewer_stats vs;
            xrad_viewer_get_stats(vw, &vs);
            st->exposure = vs.exposure; /* measured: + and - scale it from here */
        }
        if (last_frame)
            break;
    }
    return s;
}

int cmd_view(int argc, char **argv)
{
    view_opts o = {0};
    int rc = parse(argc, argv, &o);
    if (rc)
        return rc < 0 ? 0 : rc;
    xrad_error err = {0};
    xrad_scene *scene = NULL, *display_scene = NULL;
    if (method_load_scene(o.scene, &o.m, &scene, &err) ||
        method_load_scene(o.scene, &o.m, &display_scene, &err))
        return cli_report(&err);

    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        fprintf(stderr,
                "xrad view: no display: %s. Set DISPLAY (X11) or WAYLAND_DISPLAY, or run "
                "under Xvfb (xvfb-run xrad view ...)\n",
                glfw_message[0] ? glfw_message : "glfwInit failed");
        xrad_scene_destroy(&scene);
        xrad_scene_destroy(&display_scene);
        return 2;
    }
    rc = 2;
    xrad_context *ctx = NULL;
    GLFWwindow *window = NULL;
    VkSurfaceKHR win_surface = VK_NULL_HANDLE;
    xrad_scheduler *sch = NULL;
    xrad_viewer *vw = NULL;
    uint32_t ext_count = 0;
    const char **exts = glfwVulkanSupported() ? glfwGetRequiredInstanceExtensions(&ext_count)
                                              : NULL;
    if (!exts) {
        fprintf(stderr, "xrad view: no Vulkan presentation on this display: %s\n",
                glfw_message[0] ? glfw_message : "GLFW finds no Vulkan loader or surface");
        goto done;
    }
    xrad_context_desc cd = {
        .device = o.device,
        .instance_extensions = exts,
        .instance_extension_count = ext_count,
        .present = 1,
    };
    if (cli_context_create(cd, &ctx, &err)) {
        rc = cli_report(&err);
        goto done;
    }
    xrad_camera_desc home;
    xrad_scene_get_camera(display_scene, &home);
    uint32_t w = o.width, h = o.height;
    if (!w && !h) {
        w = home.width ? home.width : 960;
        h = home.height ? home.height : 720;
    } else if (!h) {
        h = w * 3 / 4;
    } else if (!w) {
        w = h * 4 / 3;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    char base[128], title[160];
    cli_basename_noext(o.scene, base, sizeof(base));
    snprintf(title, sizeof(title), "xrad view: %s", base);
    window = glfwCreateWindow((int)w, (int)h, title, NULL, NULL);
    if (!window) {
        fprintf(stderr, "xrad view: cannot open a window: %s\n", glfw_message);
        goto done;
    }
    VkResult vr = glfwCreateWindowSurface(xrad_vulkan_instance(ctx), window, NULL, &win_surface);
    if (vr != VK_SUCCESS) {
        fprintf(stderr, "xrad view: cannot make a Vulkan surface for the window: %s (%d)\n",
                glfw_message, (int)vr);
        goto done;
    }
    camera cam = {v3_from(home.position), v3_from(home.look_at), v3_from(home.up),
                  home.fov_degrees * M_PI / 180.0};
    view_state st = {
        .window = window,
        .scene = display_scene,
        .home = cam,
        .cam = cam,
        .exposure = o.exposure,
        .tonemap = o.tonemap,
        .nearest = o.nearest,
        .overlay = !o.no_overlay,
        .method = o.m.solver.method,
        .grabbed = -1,
    };
    double lo[3], hi[3];
    xrad_scene_get_bounds(display_scene, o.time, lo, hi);
    vec3 size = v3_sub(v3_from(hi), v3_from(lo));
    st.diameter = sqrt(v3_dot(size, size));
    st.move_speed = isfinite(st.diameter) && st.diameter > 0 ? 0.25 * st.diameter : 1.0;
    glfwSetWindowUserPointer(window, &st);
    glfwSetKeyCallback(window, on_key);
    glfwSetCharCallback(window, on_char);
    glfwSetMouseButtonCallback(window, on_button);
    glfwSetCursorPosCallback(window, on_cursor);
    glfwSetScrollCallback(window, on_scroll);

    int fw, fh;
    glfwGetFramebufferSize(window, &fw, &fh);
    xrad_viewer_desc vd = {.surface = win_surface,
                           .width = (uint32_t)fw,
                           .height = (uint32_t)fh,
                           .vsync = !o.no_vsync};
    xrad_scheduler_desc sd = {.solver = o.m.solver};
    sd.solver.time = o.time;
    xrad_status s = xrad_viewer_create(ctx, display_scene, &vd, &vw, &err);
    if (!s && !(s = xrad_scheduler_create(ctx, scene, &sd, &sch, &err)))
        scene = NULL; /* the scheduler's now */
    if (!s) {
        if (!o.frames)
            printf("xrad view: %s on %s; press ? or F1 for the keys\n", o.scene,
                   xrad_context_device_name(ctx));
        s = run(&o, &st, sch, vw, &err);
    }
    if (sch && vw)
        print_summary(sch, vw);
    if (s) {
        rc = cli_report(&err);
    } else {
        rc = 0;
        if (o.screenshot)
            printf("screenshot: %s\n", o.screenshot);
    }
    xrad_scheduler_destroy(&sch);
    xrad_viewer_destroy(&vw);
    if (ctx && xrad_context_validation_messages(ctx)) {
        fprintf(stderr, "xrad view: %u validation messages\n",
                xrad_context_validation_messages(ctx));
        rc = rc ? rc : 2;
    }

done:
    if (win_surface)
        vkDestroySurfaceKHR(xrad_vulkan_instance(ctx), win_surface, NULL);
    if (window)
        glfwDestroyWindow(window);
    xrad_context_destroy(&ctx);
    glfwTerminate();
    xrad_scene_destroy(&scene);
    xrad_scene_destroy(&display_scene);
    return rc;
}
