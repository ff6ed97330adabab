/* A C host driving libfractum: the SHPB specimen, then a dlsm and a beam2d scene.
 *
 * Build (from the repository root, after `cargo build --release -p fractum-ffi`):
 *   gcc -std=c11 -Wall -Wextra -Iinclude ffi/examples/host.c -Ltarget/release -lfractum \
 *       -Wl,-rpath,$PWD/target/release -o host
 *   ./host scenes/shpb_sand.toml
 *
 * It compresses the sample at 3 m/s from the incident face for 20 communication steps of
 * 5 microseconds, prints the face stresses, checks that the stress rises with strain, that a
 * saved state replays bit for bit, and that bad calls are refused with a status and a
 * message. Then it drives a reduced dlsm tension scene and a reduced beam2d moduli scene
 * through the same generic calls (advance, clock, per-body copies, a named series value, the
 * summary as JSON, save/restore, reset) and checks that the SHPB-only calls are refused on
 * them with FRACTUM_ERR_MODEL. Exit code 0 when all holds.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fractum.h"

static int failures = 0;

#define CHECK(cond, ...)                                   \
    do {                                                   \
        if (!(cond)) {                                     \
            fprintf(stderr, "host.c: FAILED: " __VA_ARGS__); \
            fprintf(stderr, "\n");                         \
            failures++;                                    \
        }                                                  \
    } while (0)

static FractumStatus must(FractumStatus s, const char *what) {
    if (s != FRACTUM_OK) {
        fprintf(stderr, "host.c: %s failed (%d): %s\n", what, (int)s, fractum_last_error());
        exit(1);
    }
    return s;
}

static double absd(double x) { return x < 0.0 ? -x : x; }

/* The summary as JSON text: ask for the size, then fetch it (the caller frees it). */
static char *summary_json(FractumHandle sim) {
    size_t needed = 0;
    FractumStatus s = fractum_summary_json(sim, NULL, 0, &needed);
    CHECK(s == FRACTUM_ERR_BUFFER && needed > 2, "the size query answers (%d, %zu)", (int)s, needed);
    char *json = malloc(needed);
    must(fractum_summary_json(sim, json, needed, &needed), "summary_json");
    CHECK(json[0] == '{' && json[needed - 2] == '}', "a JSON object: %s", json);
    return json;
}

/* Copies 3 (or 4) doubles per body and checks they are finite. */
static double *copy_per_body(FractumHandle sim, int per_body, const char *what) {
    uint64_t n = 0;
    must(fractum_bodies(sim, &n), "bodies");
    size_t len = (size_t)per_body * n;
    double *v = malloc(sizeof(double) * len);
    FractumStatus s = per_body == 4 ? fractum_copy_orientations(sim, v, len)
                      : strcmp(what, "positions") == 0 ? fractum_copy_positions(sim, v, len)
                                                       : fractum_copy_velocities(sim, v, len);
    must(s, what);
    for (size_t k = 0; k < len; k++) {
        CHECK(!isnan(v[k]) && absd(v[k]) < 1e30, "%s[%zu] = %g is finite", what, k, v[k]);
    }
    return v;
}

/* A dlsm or beam2d scene through the generic calls: the model's name, advancing by steps
   and to a time, the clock, per-body copies, a named series value, the summary as JSON,
   replay from a saved state, reset; the SHPB-only calls are refused with FRACTUM_ERR_MODEL. */
static void other_model(const char *scene, const char *const *overrides, size_t count, const char *kind,
                        uint64_t expected_bodies, int planar) {
    FractumHandle sim = 0;
    must(fractum_create_from_file(scene, overrides, count, 1, &sim), "create");
    const char *model = NULL;
    must(fractum_model(sim, &model), "model");
    CHECK(strcmp(model, kind) == 0, "%s is a %s scene (got %s)", scene, kind, model);
    uint64_t bodies = 0, steps = 0;
    must(fractum_bodies(sim, &bodies), "bodies");
    CHECK(bodies == expected_bodies, "%s: %llu bodies, expected %llu", scene, (unsigned long long)bodies,
          (unsigned long long)expected_bodies);

    /* What only a granular box answers: a clear status, a sentence naming the model. */
    double top, bottom, area, r[1];
    CHECK(fractum_set_face_speeds(sim, 3.0, 0.0) == FRACTUM_ERR_MODEL, "face speeds refused on %s", kind);
    CHECK(strstr(fractum_last_error(), kind) != NULL, "the message names the model: %s", fractum_last_error());
    CHECK(fractum_face_forces(sim, &top, &bottom) == FRACTUM_ERR_MODEL, "face forces refused on %s", kind);
    CHECK(fractum_face_stresses(sim, &top, &bottom, &area) == FRACTUM_ERR_MODEL, "face stresses refused on %s",
          kind);
    CHECK(fractum_copy_radii(sim, r, 1) == FRACTUM_ERR_MODEL, "radii refused on %s", kind);
    int32_t finished = 1;
    must(fractum_finished(sim, &finished), "finished");
    CHECK(finished == 0, "a refused call changed nothing: the run has not ended");

    /* 100 steps, saved; 150 more, remembered; replayed from the saved state. */
    must(fractum_advance(sim, 100), "advance");
    size_t state_len = 0, written = 0;
    must(fractum_state_size(sim, &state_len), "state_size");
    unsigned char *state = malloc(state_len);
    must(fractum_save_state(sim, state, state_len, &written), "save_state");
    must(fractum_advance(sim, 150), "advance");
    double t = 0.0, dt = 0.0, strain = 0.0;
    must(fractum_steps(sim, &steps), "steps");
    must(fractum_time(sim, &t), "time");
    must(fractum_dt(sim, &dt), "dt");
    CHECK(steps == 250, "250 steps taken (%llu)", (unsigned long long)steps);
    CHECK(absd(t - 250 * dt) < 1e-9 * t, "t = %g after 250 steps of %g s", t, dt);
    must(fractum_progress(sim, &t, &strain, &steps), "progress");
    CHECK(isnan(strain), "no granular box: the progress strain is NaN (%g)", strain);

    double *pos = copy_per_body(sim, 3, "positions");
    double *vel = copy_per_body(sim, 3, "velocities");
    double *quat = copy_per_body(sim, 4, "orientations");
    double speed = 0.0;
    for (uint64_t i = 0; i < bodies; i++) {
        double *q = quat + 4 * i;
        CHECK(absd(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1.0) < 1e-9, "unit quaternion %llu",
              (unsigned long long)i);
        if (planar) {
            CHECK(pos[3 * i + 2] == 0.0 && vel[3 * i + 2] == 0.0 && q[1] == 0.0 && q[2] == 0.0,
                  "a 2D polygon stays in the plane and turns about z (%llu)", (unsigned long long)i);
        }
        speed += absd(vel[3 * i]) + absd(vel[3 * i + 1]) + absd(vel[3 * i + 2]);
    }
    CHECK(speed > 0.0, "the loading moves the bodies");
    CHECK(fractum_copy_orientations(sim, quat, 4 * bodies - 1) == FRACTUM_ERR_BUFFER, "a short buffer is refused");

    /* A named value of the last series row; an unknown name lists the columns. */
    double ke = -1.0, row_time = -1.0;
    must(fractum_scalar(sim, "kinetic_energy", &ke), "scalar kinetic_energy");
    must(fractum_scalar(sim, "time", &row_time), "scalar time");
    CHECK(ke > 0.0 && row_time > 0.0 && row_time <= t, "kinetic energy %g J at the row of t = %g s", ke, row_time);
    CHECK(fractum_scalar(sim, "no_such_column", &ke) == FRACTUM_ERR_INPUT, "an unknown column is refused");
    CHECK(strstr(fractum_last_error(), "kinetic_energy") != NULL, "the message lists the columns: %s",
          fractum_last_error());
    char columns[512];
    size_t needed = 0;
    must(fractum_columns(sim, columns, sizeof columns, &needed), "columns");
    CHECK(strncmp(columns, "time,", 5) == 0 && needed == strlen(columns) + 1, "columns: %s", columns);

    char *json = summary_json(sim);
    char expect[64];
    snprintf(expect, sizeof expect, "\"model\": \"%s\"", kind);
    CHECK(strstr(json, expect) != NULL, "the summary names the model: %.200s", json);
    CHECK(strstr(json, "\"steps\": 250,") != NULL, "the summary counts the steps: %.300s", json);
    printf("%s: %llu bodies, t = %.4e s, kinetic energy %.4e J, summary of %zu bytes\n", kind,
           (unsigned long long)bodies, t, ke, strlen(json));
    free(json);

    /* Replay: bit for bit. */
    must(fractum_restore_state(sim, state, state_len), "restore_state");
    must(fractum_advance(sim, 150), "advance after restore");
    double *again = copy_per_body(sim, 3, "positions");
    CHECK(memcmp(pos, again, sizeof(double) * 3 * bodies) == 0, "%s replays bit for bit", kind);
    free(again);

    /* Landing on a time between steps: a variable-step integrator shortens the last step;
       beam2d's Gear5 takes whole steps only and refuses, leaving the run as it was. */
    must(fractum_time(sim, &t), "time");
    FractumStatus s = fractum_advance_to(sim, t + 0.5 * dt);
    char message[512];
    snprintf(message, sizeof message, "%s", fractum_last_error());
    double t2 = 0.0;
    must(fractum_time(sim, &t2), "time");
    if (planar) {
        CHECK(s == FRACTUM_ERR_RUN && t2 == t, "Gear5 refuses to land off its grid (%d)", (int)s);
        CHECK(strstr(message, "whole steps") != NULL, "message: %s", message);
    } else {
        CHECK(s == FRACTUM_OK && t2 == t + 0.5 * dt, "lands on t + dt/2 (%d, %.17g)", (int)s, t2);
    }

    must(fractum_reset(sim), "reset");
    must(fractum_steps(sim, &steps), "steps");
    CHECK(steps == 0, "reset to step 0 (%llu)", (unsigned long long)steps);
    must(fractum_free(sim), "free");
    CHECK(fractum_model(sim, &model) == FRACTUM_ERR_HANDLE, "a freed handle is refused");
    free(state);
    free(pos);
    free(vel);
    free(quat);
}

int main(int argc, char **argv) {
    const char *scene = argc > 1 ? argv[1] : "scenes/shpb_sand.toml";
    const char *overrides[] = {"output.vtk=0", "output.every=1000000"};
    FractumHandle sim = 0;
    printf("libfractum %s\n", fractum_version());
    must(fractum_create_from_file(scene, overrides, 2, 1, &sim), "create");

    uint64_t bodies = 0, contacts = 0;
    double ke = 0.0;
    must(fractum_counts(sim, &bodies, &contacts, &ke), "counts");
    printf("%llu bodies\n", (unsigned long long)bodies);
    const char *model = NULL;
    must(fractum_model(sim, &model), "model");
    CHECK(strcmp(model, "granular") == 0, "%s is a granular scene (got %s)", scene, model);

    /* The incident bar pushes the top face in at 3 m/s; the transmitted face stays. */
    must(fractum_set_face_speeds(sim, 3.0, 0.0), "set_face_speeds");
    double t = 0.0, strain = 0.0;
    uint64_t steps = 0;
    size_t state_len = 0;
    unsigned char *state = NULL;
    double top_at_5 = 0.0, top_at_10 = 0.0;
    for (int k = 1; k <= 20; k++) {
        if (k == 10) {
            must(fractum_state_size(sim, &state_len), "state_size");
            state = malloc(state_len);
            size_t written = 0;
            must(fractum_save_state(sim, state, state_len, &written), "save_state");
            CHECK(written == state_len, "saved %zu of %zu bytes", written, state_len);
        }
        must(fractum_advance_to(sim, 5e-6 * k), "advance_to");
        double top, bottom, area;
        must(fractum_face_stresses(sim, &top, &bottom, &area), "face_stresses");
        must(fractum_progress(sim, &t, &strain, &steps), "progress");
        printf("t = %.3e s  strain = %.5f  stress top = %.4e Pa  bottom = %.4e Pa\n", t, strain, top, bottom);
        CHECK(t == 5e-6 * k, "lands exactly on the requested time (%.17g)", t);
        if (k == 5) {
            top_at_5 = top;
        }
        if (k == 10) {
            top_at_10 = top;
        }
    }
    /* The stress rises with strain: from 1.25% to 5% a Hertz packing with a fixed contact
     * network stiffens by (5/1.25)^1.5 = 8; grains that break soften it, and a breaking grain
     * can dip the stress between two samples, so ask for half that over the whole range. */
    double top_end, bottom_end, area_end;
    must(fractum_face_stresses(sim, &top_end, &bottom_end, &area_end), "face_stresses");
    CHECK(top_end > 4.0 * top_at_5, "the stress rises with strain (%g at 5%%, %g at 1.25%%)",
          top_end, top_at_5);
    CHECK(strain > 0.0499 && strain < 0.0501, "strain %g after 100 us at 3 m/s over 6 mm", strain);

    /* Replay from the saved state: the same stresses, bit for bit. */
    must(fractum_restore_state(sim, state, state_len), "restore_state");
    must(fractum_advance_to(sim, 5e-5), "advance_to after restore");
    double top, bottom, area;
    must(fractum_face_stresses(sim, &top, &bottom, &area), "face_stresses");
    CHECK(top == top_at_10, "replay gives %.17g, first pass %.17g", top, top_at_10);
    free(state);

    /* Arrays into caller buffers; a short buffer is refused. Grains break, so the body
       count is read again now. */
    must(fractum_counts(sim, &bodies, &contacts, &ke), "counts");
    double *pos = malloc(sizeof(double) * 3 * bodies);
    must(fractum_copy_positions(sim, pos, 3 * bodies), "copy_positions");
    CHECK(pos[2] > 0.0 && pos[2] < 6e-3, "positions inside the box (z0 = %g)", pos[2]);
    CHECK(fractum_copy_positions(sim, pos, 2) == FRACTUM_ERR_BUFFER, "a short buffer is refused");
    CHECK(strstr(fractum_last_error(), "needed") != NULL, "message: %s", fractum_last_error());
    free(pos);
    double *quat = copy_per_body(sim, 4, "orientations");
    CHECK(absd(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3] - 1.0) < 1e-9,
          "unit quaternions");
    free(quat);
    double row_strain = -1.0;
    must(fractum_scalar(sim, "axial_strain", &row_strain), "scalar axial_strain");
    CHECK(row_strain >= 0.0 && row_strain <= strain, "the last row's strain %g (now %g)", row_strain, strain);
    char *json = summary_json(sim);
    CHECK(strstr(json, "\"model\": \"granular\"") != NULL, "the summary names the model: %.200s", json);
    free(json);

    /* Reset returns to the state right after creation. */
    must(fractum_reset(sim), "reset");
    must(fractum_progress(sim, &t, &strain, &steps), "progress");
    CHECK(t == 0.0 && steps == 0, "reset to t = 0 (t = %g, %llu steps)", t, (unsigned long long)steps);

    /* Bad calls: null pointers, stale handles, bad input. */
    CHECK(fractum_progress(sim, NULL, &strain, &steps) == FRACTUM_ERR_NULL, "null output refused");
    must(fractum_free(sim), "free");
    CHECK(fractum_advance_to(sim, 1e-6) == FRACTUM_ERR_HANDLE, "a freed handle is refused");
    CHECK(fractum_free(sim) == FRACTUM_ERR_HANDLE, "a double free is refused");
    CHECK(fractum_advance_to(12345, 1e-6) == FRACTUM_ERR_HANDLE, "a forged handle is refused");
    const char *bad[] = {"material.poisson=0.7"};
    FractumHandle other = 0;
    CHECK(fractum_create_from_file(scene, bad, 1, 1, &other) == FRACTUM_ERR_INPUT, "bad input refused");
    CHECK(strstr(fractum_last_error(), "material.poisson") != NULL, "message names the key: %s",
          fractum_last_error());
    CHECK(fractum_create_from_file(NULL, NULL, 0, 1, &other) == FRACTUM_ERR_NULL, "null path refused");

    /* The other models, reduced (the sizes of tests/golden_summaries.rs). */
    const char *dlsm[] = {"sample.elements=300"};
    other_model("scenes/dlsm_tensile.toml", dlsm, 1, "dlsm", 300, 0);
    const char *beam2d[] = {"sample.cells=[8, 12]", "loading.strain_rate=0.4", "loading.ramp_time=0.001"};
    other_model("scenes/beam2d_moduli.toml", beam2d, 3, "beam2d", 96, 1);

    if (failures == 0) {
        printf("host.c: ok\n");
        return 0;
    }
    return 1;
}
