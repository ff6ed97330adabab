# Runs inside YADE's Python: `yade -n -x tests/python/yade_wrapper.py`, with FRACTUM_ROOT (the
# repository) set and the package installed by `pip install --target DIR ./ffi/python` on
# PYTHONPATH (no FRACTUM_LIB: the library comes inside the package); YADE's __file__ is not this
# script's path.
# Drives the Fractum SHPB specimen through the ctypes wrapper and turns its grains into YADE
# spheres, to show the two living in one process.
import os

root = os.environ.get("FRACTUM_ROOT", os.getcwd())
import fractum  # noqa: E402

print("yade: fractum from %s" % os.path.dirname(fractum.__file__))

with fractum.Simulation(os.path.join(root, "scenes", "shpb_sand.toml"),
                        overrides=["output.vtk=0", "output.every=1000000000"]) as sim:
    sim.set_face_speeds(3.0, 0.0)
    sim.advance_to(2e-5)
    top, bottom, area = sim.face_stresses()
    xyz, r = sim.positions(), sim.radii()
    assert top > 1e5, top
    # The grains as YADE bodies (O and utils come with YADE's Python).
    ids = [O.bodies.append(utils.sphere(tuple(p), float(rr))) for p, rr in zip(xyz, r)]  # noqa: F821
    assert len(O.bodies) == len(r)  # noqa: F821
    print("yade: %d Fractum grains as YADE spheres, stress %.3e Pa, fractum %s" % (len(ids), top, fractum.version()))
print("yade: ok")
