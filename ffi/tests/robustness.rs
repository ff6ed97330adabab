//! Bad input at the C ABI (ffi/tests/robustness.c, compiled with gcc against
//! include/fractum.h and libfractum.so): a saved state of another scene is refused for each
//! model (granular, dlsm, beam2d) with a sentence naming whose it is; a state resealed over a
//! NaN is refused instead of panicking at the next step; `UINT64_MAX` steps on a run without
//! an end is refused unless the call is bounded; freeing a handle stops another thread's
//! unbounded `fractum_advance_to`; and `fractum_advance_to` past the end stops there as
//! `fractum_advance` does.

mod common;

use std::process::Command;

#[test]
fn the_c_abi_refuses_foreign_and_forged_states_and_stops_what_it_starts() {
    let exe = common::compile("gcc", "ffi/tests/robustness.c", "-std=gnu11");
    let run = Command::new(&exe)
        .current_dir(common::repo())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("robustness.c: ok"), "{stdout}");
    for model in ["granular", "dlsm", "beam2d"] {
        assert!(
            stdout.contains(&format!(
                "{model}: refused: the saved state belongs to another scene"
            )),
            "{stdout}"
        );
    }
}
