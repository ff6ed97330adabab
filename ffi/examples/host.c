/* A C host driving the SHPB specimen through libfractum.
 *
 * Build (from the repository root, after `cargo build --release -p fractum-ffi`):
 *   gcc -std=c11 -Wall -Wextra -Iinclude ffi/examples/host.c -Ltarget/release -lfractum \
 *       -Wl,-rpath,$PWD/target/release -o host
 *   ./host scenes/shpb_sand.toml
 *
 * It compresses the sample at 3 m/s from the incident face for 20 communication steps of
 * 5 microseconds, prints the face stresses, checks that the stress rises with strain, that a
 * saved state replays bit for bit, and that bad calls are refused with a status and a
 * message. Exit code 0 when all holds.
 */
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

    /* The incident bar pushes the top face in at 3 m/s; the transmitted face stays. */
    must(fractum_set_face_speeds(sim, 3.0, 0.0), "set_face_speeds");
    double previous = -1.0, t = 0.0, strain = 0.0;
    uint64_t steps = 0;
    size_t state_len = 0;
    unsigned char *state = NULL;
    double top_at_10 = 0.0;
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
        if (k > 4) {
            CHECK(top > previous, "the stress rises with strain (%g after %g)", top, previous);
        }
        if (k == 10) {
            top_at_10 = top;
        }
        previous = top;
    }
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

    if (failures == 0) {
        printf("host.c: ok\n");
        return 0;
    }
    return 1;
}
