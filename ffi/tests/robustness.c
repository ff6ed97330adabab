/* Bad input at the C ABI: saved states of another scene, a forged state with a NaN inside,
 * too many steps for a run without an end, freeing a handle while another thread advances
 * it, and advancing to a time past the scene's end. Run from the repository root; prints
 * "robustness.c: ok" and exits 0 when all holds.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fractum.h"

static int failures = 0;

#define CHECK(cond, ...)                                         \
    do {                                                         \
        if (!(cond)) {                                           \
            fprintf(stderr, "robustness.c: FAILED: " __VA_ARGS__); \
            fprintf(stderr, "\n");                               \
            failures++;                                          \
        }                                                        \
    } while (0)

static void must(FractumStatus s, const char *what) {
    if (s != FRACTUM_OK) {
        fprintf(stderr, "robustness.c: %s failed (%d): %s\n", what, (int)s, fractum_last_error());
        exit(1);
    }
}

static FractumHandle create(const char *scene, const char *const *overrides, size_t count) {
    FractumHandle h = 0;
    must(fractum_create_from_file(scene, overrides, count, 1, &h), scene);
    return h;
}

static uint8_t *state_of(FractumHandle h, size_t *len) {
    must(fractum_state_size(h, len), "state_size");
    uint8_t *bytes = malloc(*len);
    size_t written = 0;
    must(fractum_save_state(h, bytes, *len, &written), "save_state");
    return bytes;
}

/* 64-bit FNV-1a, the checksum that ends a sealed state. */
static uint64_t fnv1a(const uint8_t *b, size_t n) {
    uint64_t h = 0xcbf29ce484222325ULL;
    for (size_t k = 0; k < n; k++) {
        h ^= b[k];
        h *= 0x00000100000001b3ULL;
    }
    return h;
}

/* A state of scene `theirs` restored into a handle of scene `ours` is refused with
   FRACTUM_ERR_RUN, a sentence naming whose state it is, and the handle unchanged. */
static void foreign(const char *what, FractumHandle theirs, FractumHandle ours) {
    must(fractum_advance(theirs, 3), "advance");
    size_t len = 0;
    uint8_t *state = state_of(theirs, &len);
    uint64_t before = 0, after = 0;
    must(fractum_steps(ours, &before), "steps");
    FractumStatus s = fractum_restore_state(ours, state, len);
    char *why = strdup(fractum_last_error()); /* the next call sets the last error again */
    CHECK(s == FRACTUM_ERR_RUN, "%s: a state of another scene is refused (got %d: %s)", what, (int)s, why);
    CHECK(strstr(why, "belongs to another scene") != NULL && strstr(why, "it is the state of a") != NULL,
          "%s: the refusal says whose state it is: %s", what, why);
    must(fractum_steps(ours, &after), "steps");
    CHECK(before == after, "%s: the handle is unchanged", what);
    /* Its own scene's handle takes it. */
    must(fractum_restore_state(theirs, state, len), "restore into its own scene");
    free(state);
    printf("%s: refused: %s\n", what, why);
    free(why);
}

struct advancing {
    FractumHandle h;
    FractumStatus status;
};

static void *advance_far(void *arg) {
    struct advancing *a = arg;
    a->status = fractum_advance_to(a->h, 1.0);
    return NULL;
}

static double seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(void) {
    alarm(600); /* a hang fails the test instead of stalling it */
    const char *sand = "scenes/shpb_sand.toml";
    const char *quiet[] = {"output.vtk=0", "output.every=1000000"};
    const char *smaller[] = {"output.vtk=0", "output.every=1000000", "sample.box=[4e-3, 4e-3, 4e-3]"};
    FractumHandle g = create(sand, quiet, 2), g_small = create(sand, smaller, 3);
    uint64_t n = 0, n_small = 0;
    must(fractum_bodies(g, &n), "bodies");
    must(fractum_bodies(g_small, &n_small), "bodies");
    CHECK(n != n_small, "two granular samples of %llu and %llu bodies", (unsigned long long)n,
          (unsigned long long)n_small);
    foreign("granular", g_small, g);

    const char *dlsm_soft[] = {"sample.elements=300", "material.young=1e9"};
    const char *dlsm_base[] = {"sample.elements=300"};
    FractumHandle d_soft = create("scenes/dlsm_tensile.toml", dlsm_soft, 2);
    FractumHandle d = create("scenes/dlsm_tensile.toml", dlsm_base, 1);
    foreign("dlsm", d_soft, d);

    const char *beam_base[] = {"sample.cells=[8, 12]", "loading.strain_rate=0.4", "loading.ramp_time=0.001"};
    const char *beam_soft[] = {"sample.cells=[8, 12]", "loading.strain_rate=0.4", "loading.ramp_time=0.001",
                               "material.young=5e8"};
    FractumHandle b_soft = create("scenes/beam2d_moduli.toml", beam_soft, 4);
    FractumHandle b = create("scenes/beam2d_moduli.toml", beam_base, 3);
    foreign("beam2d", b_soft, b);

    /* A state whose first body's x is NaN, sealed again with a good checksum, is refused:
       it panicked in the neighbour search at the next step. */
    {
        size_t len = 0;
        uint8_t *state = state_of(g, &len);
        double *pos = malloc(sizeof(double) * 3 * n);
        must(fractum_copy_positions(g, pos, 3 * n), "positions");
        size_t at = 0;
        int found = 0;
        for (size_t k = 0; k + 8 <= len - 8 && !found; k++) {
            if (memcmp(state + k, &pos[0], 8) == 0) {
                at = k;
                found = 1;
            }
        }
        CHECK(found, "the first body's x is in the state");
        double nan = NAN;
        memcpy(state + at, &nan, 8);
        uint64_t sum = fnv1a(state, len - 8);
        memcpy(state + len - 8, &sum, 8);
        uint64_t before = 0, after = 0;
        must(fractum_steps(g, &before), "steps");
        FractumStatus s = fractum_restore_state(g, state, len);
        const char *why = fractum_last_error();
        CHECK(s == FRACTUM_ERR_RUN && strstr(why, "body 0") && strstr(why, "non-finite"),
              "a resealed NaN is refused (got %d: %s)", (int)s, why);
        must(fractum_steps(g, &after), "steps");
        CHECK(before == after, "the handle is unchanged");
        must(fractum_advance(g, 2), "the handle goes on");
        free(pos);
        free(state);
    }

    /* A run without an end (driven faces): UINT64_MAX steps in one unbounded call is refused,
       not run for days; bounded by the call limits it stops at the bound. */
    {
        must(fractum_set_face_speeds(g, 1.0, 0.0), "face speeds");
        uint64_t before = 0, after = 0;
        must(fractum_steps(g, &before), "steps");
        FractumStatus s = fractum_advance(g, UINT64_MAX);
        CHECK(s == FRACTUM_ERR_RUN && strstr(fractum_last_error(), "no end of its own"),
              "UINT64_MAX steps without an end are refused (got %d: %s)", (int)s, fractum_last_error());
        must(fractum_set_call_limits(g, 3, 0.0), "call limits");
        s = fractum_advance(g, UINT64_MAX);
        must(fractum_steps(g, &after), "steps");
        CHECK(s == FRACTUM_INTERRUPTED && after == before + 3, "bounded: 3 steps and interrupted (got %d, %llu)",
              (int)s, (unsigned long long)(after - before));
        must(fractum_set_call_limits(g, 0, 0.0), "call limits");
    }

    /* Freeing a handle while another thread advances it without bound stops that call. */
    {
        struct advancing a = {g, FRACTUM_OK};
        pthread_t thread;
        CHECK(pthread_create(&thread, NULL, advance_far, &a) == 0, "thread starts");
        usleep(300000);
        double t0 = seconds();
        must(fractum_free(g), "free during an advance");
        pthread_join(thread, NULL);
        CHECK(a.status == FRACTUM_INTERRUPTED, "the advance stopped (got %d)", (int)a.status);
        CHECK(seconds() - t0 < 30.0, "within a step or so (%.1f s)", seconds() - t0);
    }

    /* advance_to a time past the end stops at the end, as advance does. */
    {
        FractumHandle by_steps = create("scenes/dlsm_tensile.toml", dlsm_base, 1);
        FractumHandle by_time = create("scenes/dlsm_tensile.toml", dlsm_base, 1);
        must(fractum_advance(by_steps, UINT64_MAX), "advance to the end");
        double end = 0.0, t = 0.0;
        uint64_t steps = 0, steps_t = 0;
        int32_t finished = 0;
        must(fractum_time(by_steps, &end), "time");
        must(fractum_steps(by_steps, &steps), "steps");
        must(fractum_advance_to(by_time, 10.0 * end), "advance_to past the end");
        must(fractum_time(by_time, &t), "time");
        must(fractum_steps(by_time, &steps_t), "steps");
        must(fractum_finished(by_time, &finished), "finished");
        CHECK(finished == 1 && steps_t == steps && t == end,
              "advance_to stops at the end: finished %d, %llu steps to t = %g s (advance: %llu to %g s)", finished,
              (unsigned long long)steps_t, t, (unsigned long long)steps, end);
        fractum_free(by_steps);
        fractum_free(by_time);
    }

    {
        /* A negative thread count was taken as 0 (every core). */
        FractumHandle none = 0;
        FractumStatus s = fractum_create_from_file(sand, quiet, 2, -1, &none);
        CHECK(s == FRACTUM_ERR_INPUT && strstr(fractum_last_error(), "threads") &&
                  strstr(fractum_last_error(), "-1 is outside the allowed range [0, "),
              "threads = -1 is refused (got %d: %s)", (int)s, fractum_last_error());
        CHECK(none == 0, "no handle for a refused thread count");
    }

    fractum_free(g_small);
    fractum_free(d_soft);
    fractum_free(d);
    fractum_free(b_soft);
    fractum_free(b);
    if (failures == 0) {
        printf("robustness.c: ok\n");
    }
    return failures == 0 ? 0 : 1;
}
