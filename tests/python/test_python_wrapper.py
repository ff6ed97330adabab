"""The ctypes wrapper (ffi/python/fractum.py) on the SHPB scene, in plain Python."""
import os

import numpy as np
import pytest

import fractum

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENE = os.path.join(ROOT, "scenes", "shpb_sand.toml")
QUIET = ["output.vtk=0", "output.every=1000000"]


def test_stress_rises_with_strain_and_arrays_come_back_as_numpy():
    with fractum.Simulation(SCENE, overrides=QUIET) as sim:
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
