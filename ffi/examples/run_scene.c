/* Runs any scene to its end through libfractum and prints its summary as JSON: what
 * `fractum run SCENE --threads N --set KEY=VALUE ...` computes, without the output files.
 *
 * Build (from the repository root, after `cargo build --release -p fractum-ffi`):
 *   gcc -std=c11 -Wall -Wextra -Iinclude ffi/examples/run_scene.c -Ltarget/release -lfractum \
 *       -Wl,-rpath,$PWD/target/release -o run_scene
 *   ./run_scene scenes/dlsm_tensile.toml 1 1000 sample.elements=300
 *
 * Arguments: the scene file, the thread count (0 = every core), the steps per call of
 * fractum_advance (how the run is chunked does not change it), then KEY=VALUE overrides.
 * The summary (the keys of summary.json but wall_seconds) goes to stdout; progress and
 * errors go to stderr. Exit code 0 on success, 1 when a call fails, 2 on bad arguments.
 */
#include <stdio.h>
#include <stdlib.h>

#include "fractum.h"

static void must(FractumStatus s, const char *what) {
    if (s != FRACTUM_OK) {
        fprintf(stderr, "run_scene: %s failed (%d): %s\n", what, (int)s, fractum_last_error());
        exit(1);
    }
}

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: run_scene SCENE THREADS STEPS_PER_CALL [KEY=VALUE ...]\n");
        return 2;
    }
    const char *scene = argv[1];
    int threads = atoi(argv[2]);
    unsigned long long chunk = strtoull(argv[3], NULL, 10);
    if (chunk == 0) {
        fprintf(stderr, "run_scene: STEPS_PER_CALL must be at least 1\n");
        return 2;
    }
    const char *const *overrides = (const char *const *)(argv + 4);
    size_t count = (size_t)(argc - 4);

    FractumHandle sim = 0;
    must(fractum_create_from_file(scene, overrides, count, threads, &sim), "create");
    const char *model = NULL;
    uint64_t bodies = 0;
    must(fractum_model(sim, &model), "model");
    must(fractum_bodies(sim, &bodies), "bodies");
    fprintf(stderr, "run_scene: %s, a %s run of %llu bodies on %d thread(s)\n", scene, model,
            (unsigned long long)bodies, threads);

    int32_t finished = 0;
    must(fractum_finished(sim, &finished), "finished");
    while (!finished) {
        must(fractum_advance(sim, chunk), "advance");
        must(fractum_finished(sim, &finished), "finished");
    }

    /* Ask for the size, then fetch the text. */
    size_t needed = 0;
    FractumStatus s = fractum_summary_json(sim, NULL, 0, &needed);
    if (s != FRACTUM_ERR_BUFFER || needed == 0) {
        fprintf(stderr, "run_scene: the size query gave %d (needed %zu)\n", (int)s, needed);
        return 1;
    }
    char *json = malloc(needed);
    if (json == NULL) {
        fprintf(stderr, "run_scene: out of memory\n");
        return 1;
    }
    must(fractum_summary_json(sim, json, needed, &needed), "summary_json");
    printf("%s\n", json);
    free(json);
    must(fractum_free(sim), "free");
    return 0;
}
