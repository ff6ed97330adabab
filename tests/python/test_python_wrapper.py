"""The ctypes wrapper (ffi/python/fractum) in plain Python: the SHPB scene, then reduced
dlsm and beam2d scenes through the generic calls."""
import ctypes
import os

import numpy as np
import pytest

import fractum

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENE = os.path.join(ROOT, "scenes", "shpb_sand.toml")
QUIET = ["output.vtk=0", "output.every=1000000"]


def test_stress_rises_with_strain_and_arrays_come_back_as_numpy():
    with fractum.Simulation(SCENE, overrides=QUIET) as sim:
        assert sim.model == "granular"
        n, contacts, ke = sim.counts()
        assert 900 < n < 1050
        r = sim.radii()
        assert r.shape == (n,) and (r >= 0.1e-3).all() and (r <= 0.45e-3).all()
        x = sim.positions()
        assert x.shape == (n, 3) and (x > 0).all() and (x < 6e-3).all()
        sim.set_face_speeds(3.0, 0.0)
        stresses = []
        for k in range(1, 11):
            sim.advance_to(1e-5 * k)
            t, strain, steps = sim.progress()
            assert t == pytest.approx(1e-5 * k, rel=0, abs=0)
            stresses.append(sim.face_stresses()[0])
        assert strain == pytest.approx(0.05, rel=1e-3)  # 3 m/s x 100 us / 6 mm
        assert all(b > a for a, b in zip(stresses[2:], stresses[3:]))
        # Grains break (the scene has the fracture effect): the arrays follow the bodies now.
        n_now = sim.counts()[0]
        assert n_now >= n
        v = sim.velocities()
        assert v.shape == (n_now, 3) and np.isfinite(v).all()


def test_saved_state_replays_bit_for_bit_and_reset_returns_to_the_start():
    with fractum.Simulation(SCENE, overrides=QUIET) as sim:
        sim.set_face_speeds(3.0, 0.0)
        sim.advance_to(2e-5)
        state = sim.save_state()
        sim.advance_to(4e-5)
        first = (sim.face_stresses(), sim.positions())
        sim.restore_state(state)
        sim.advance_to(4e-5)
        again = (sim.face_stresses(), sim.positions())
        assert first[0] == again[0]
        assert np.array_equal(first[1], again[1])
        sim.reset()
        assert sim.progress() == (0.0, 0.0, 0)


def test_damaged_state_blobs_are_refused_and_leave_the_run_as_it_was():
    # blobs carry a format version and a checksum (src/output/sealed.rs).
    with fractum.Simulation(SCENE, overrides=QUIET) as sim:
        sim.set_face_speeds(3.0, 0.0)
        sim.advance_to(1e-6)
        state = bytes(sim.save_state())
        sim.advance_to(2e-6)
        before = sim.positions()
        rng = np.random.default_rng(16)
        spots = list(rng.integers(0, len(state), 40)) + [0, 8, 12, len(state) - 1]
        for byte in spots:
            damaged = bytearray(state)
            damaged[byte] ^= 1 << int(rng.integers(0, 8))
            with pytest.raises(fractum.FractumError) as e:
                sim.restore_state(bytes(damaged))
            assert e.value.status == "FRACTUM_ERR_RUN", (byte, e.value.message)
            assert "not usable" in e.value.message, (byte, e.value.message)
        for cut in (0, 10, len(state) // 2, len(state) - 1):
            with pytest.raises(fractum.FractumError):
                sim.restore_state(state[:cut])
        assert np.array_equal(sim.positions(), before)
        sim.restore_state(state)
        assert sim.progress()[0] == pytest.approx(1e-6, rel=1e-12)


def test_advance_calls_can_be_bounded_and_cancelled():
    # with still faces advance_to(1e9) ran indefinitely.
    import threading
    import time as clock

    with fractum.Simulation(SCENE, overrides=QUIET) as sim:
        sim.set_face_speeds(0.0, 0.0)
        sim.set_call_limits(max_steps=30)
        with pytest.raises(fractum.Interrupted) as e:
            sim.advance_to(1e9)
        assert e.value.status == "FRACTUM_INTERRUPTED" and "30 steps" in e.value.message
        assert sim.progress()[2] == 30
        with pytest.raises(fractum.Interrupted):
            sim.advance(1000)
        assert sim.progress()[2] == 60
        sim.advance(10)  # within the bound: completes
        assert sim.progress()[2] == 70
        sim.set_call_limits(max_seconds=0.2)
        with pytest.raises(fractum.Interrupted) as e:
            sim.advance_to(1e9)
        assert "wall time" in e.value.message
        steps = sim.progress()[2]
        assert steps > 70
        # Cancelled from another thread while a call without bounds runs.
        sim.set_call_limits()
        threading.Timer(0.3, sim.cancel).start()
        with pytest.raises(fractum.Interrupted) as e:
            sim.advance_to(1e9)
        assert "cancelled" in e.value.message and sim.progress()[2] > steps
        # The stop cleared the request: the next call runs to its target.
        t = sim.time()
        sim.advance_to(t + 1e-8)
        assert sim.time() == t + 1e-8
        with pytest.raises(fractum.FractumError) as e:
            sim.set_call_limits(max_seconds=-1.0)
        assert e.value.status == "FRACTUM_ERR_INPUT" and "max_seconds" in e.value.message


def test_failures_raise_with_the_status_and_a_sentence():
    with pytest.raises(fractum.FractumError) as e:
        fractum.Simulation(SCENE, overrides=["material.poisson=0.7"])
    assert e.value.status == "FRACTUM_ERR_INPUT"
    assert "material.poisson" in e.value.message and "(-1, 0.5)" in e.value.message
    sim = fractum.Simulation(SCENE, overrides=QUIET)
    sim.close()
    with pytest.raises(fractum.FractumError) as e:
        sim.advance_to(1e-6)
    assert e.value.status == "FRACTUM_ERR_HANDLE"
    assert fractum.version()
    # More threads than cores: refused with the option and the core count, not a hang.
    with pytest.raises(fractum.FractumError) as e:
        fractum.Simulation(SCENE, overrides=QUIET, threads=100000)
    assert e.value.status == "FRACTUM_ERR_INPUT"
    assert "100000" in e.value.message and "cores" in e.value.message


def test_thread_counts_that_wrap_or_are_negative_and_nul_in_text_are_refused():
    # ctypes wraps an int into the C ABI's int32_t: threads=2**40 ran on every core, 2**32 + 1
    # on one, and -1 was taken as every core; a NUL cut a scene text short without a word.
    for bad in (-1, -(2**31), 2**31, 2**32 + 1, 2**40):
        with pytest.raises(ValueError, match=r"threads = .* outside the allowed range \[0, "):
            fractum.Simulation(SCENE, overrides=QUIET, threads=bad)
    for bad in (1.5, "2", None, True):
        with pytest.raises(TypeError, match="whole number"):
            fractum.Simulation(SCENE, overrides=QUIET, threads=bad)
    text = open(SCENE).read()
    with pytest.raises(ValueError, match="NUL character at offset 5"):
        fractum.Simulation(text=text[:5] + "\0" + text[5:], base_dir=os.path.dirname(SCENE))
    with pytest.raises(ValueError, match=r"overrides\[1\] holds a NUL"):
        fractum.Simulation(SCENE, overrides=["output.vtk=0", "seed=1\0"])
    # The C ABI refuses a negative count itself (another caller than this wrapper).
    lib = fractum.load_library()
    handle = ctypes.c_uint64(0)
    none = (ctypes.c_char_p * 1)()
    status = lib.fractum_create_from_file(SCENE.encode(), none, 0, -1, ctypes.byref(handle))
    assert fractum._STATUS[status] == "FRACTUM_ERR_INPUT"
    with fractum.Simulation(SCENE, overrides=QUIET, threads=np.int64(1)) as sim:
        assert sim.steps() == 0


def test_step_counts_must_be_whole_and_not_negative():
    # int() made advance(-1) 2^64 - 1 steps (a run to the scene's end) and advance(1.5) one.
    scene = os.path.join(ROOT, "scenes", "beam2d_moduli.toml")
    with fractum.Simulation(scene, overrides=["sample.cells=[8, 12]"]) as sim:
        for call in (sim.advance, sim.set_call_limits):
            for bad in (-1, -(2**63), 2**64):
                with pytest.raises(ValueError, match="outside the allowed range"):
                    call(bad)
            for bad in (1.5, 2.0, "3", None, True):
                with pytest.raises(TypeError, match="whole number"):
                    call(bad)
        assert sim.steps() == 0
        sim.advance(np.int64(2))
        sim.advance(1)
        assert sim.steps() == 3


# The reduced sizes of tests/golden_summaries.rs.
OTHER_MODELS = [
    ("dlsm_tensile.toml", ["sample.elements=300"], "dlsm", 300),
    ("beam2d_moduli.toml",
     ["sample.cells=[8, 12]", "loading.strain_rate=0.4", "loading.ramp_time=0.001"], "beam2d", 96),
]


@pytest.mark.parametrize("scene,overrides,model,bodies", OTHER_MODELS, ids=[m[2] for m in OTHER_MODELS])
def test_dlsm_and_beam2d_run_to_their_end_through_the_generic_calls(scene, overrides, model, bodies):
    with fractum.Simulation(os.path.join(ROOT, "scenes", scene), overrides=overrides) as sim:
        assert sim.model == model
        assert sim.bodies() == bodies and sim.counts()[0] == bodies
        # The SHPB calls, radii and grain loads do not apply: ModelError, a FractumError naming
        # the model.
        for call in (lambda: sim.set_face_speeds(3.0, 0.0), sim.face_forces, sim.face_stresses,
                     sim.radii, sim.grain_loads):
            with pytest.raises(fractum.ModelError) as e:
                call()
            assert e.value.status == "FRACTUM_ERR_MODEL" and model in e.value.message
        assert not sim.finished()
        sim.advance(100)
        state = sim.save_state()
        sim.advance(100)
        assert sim.steps() == 200 and sim.time() == pytest.approx(200 * sim.dt(), rel=1e-9)
        x, v, q = sim.positions(), sim.velocities(), sim.orientations()
        assert x.shape == v.shape == (bodies, 3) and q.shape == (bodies, 4)
        assert np.isfinite(x).all() and np.isfinite(v).all() and np.abs(v).sum() > 0
        assert np.allclose((q * q).sum(axis=1), 1.0, rtol=0, atol=1e-9)
        if model == "beam2d":
            assert (x[:, 2] == 0).all() and (q[:, 1:3] == 0).all()
        t, strain, steps = sim.progress()
        assert steps == 200 and np.isnan(strain)
        sim.restore_state(state)
        sim.advance(100)
        assert np.array_equal(sim.positions(), x)
        columns = sim.columns()
        assert columns[0] == "time" and "kinetic_energy" in columns
        with pytest.raises(fractum.FractumError) as e:
            sim.scalar("no_such_column")
        assert e.value.status == "FRACTUM_ERR_INPUT" and "kinetic_energy" in e.value.message
        while not sim.finished():
            sim.advance(1000)
        assert sim.scalar("time") == sim.time()  # the last row is recorded at the end
        assert sim.scalar("kinetic_energy") > 0
        summary = sim.summary()
        assert summary["model"] == model and summary["bodies"] == bodies
        assert summary["steps"] == sim.steps() and "wall_seconds" not in summary
        if model == "dlsm":
            assert summary["apparent_young"] == pytest.approx(20e9, rel=0.1)
        else:
            assert summary["integrator"] == "gear5"
            with pytest.raises(fractum.FractumError) as e:
                sim.advance_to(sim.time() + 0.5 * sim.dt())
            assert e.value.status == "FRACTUM_ERR_RUN" and "whole steps" in e.value.message
        sim.reset()
        assert sim.steps() == 0 and sim.time() == 0.0
