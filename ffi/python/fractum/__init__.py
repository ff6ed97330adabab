"""Fractum from Python: a ctypes wrapper over libfractum.so, returning numpy arrays.

Any scene runs (granular, dlsm, beam2d); the SHPB calls (face speeds, forces and stresses)
and radii apply to granular samples only and raise ModelError on the other models.

Works in plain Python (3.8+) and in YADE's Python. `pip install ./ffi/python` builds
libfractum.so and installs it inside the package. The library is found through $FRACTUM_LIB,
else inside the installed package, else in the repository's target/release/ (with ffi/python
on sys.path), else by the system loader ("libfractum.so").

    import fractum
    with fractum.Simulation("scenes/shpb_sand.toml", overrides=["output.vtk=0"]) as sim:
        sim.set_face_speeds(3.0, 0.0)          # m/s into the sample, top and bottom
        sim.advance_to(1e-5)                   # s, lands exactly
        top, bottom, area = sim.face_stresses()  # Pa, Pa, m^2
        xyz = sim.positions()                  # (n, 3) array, m

    with fractum.Simulation("scenes/dlsm_tensile.toml", overrides=["sample.elements=300"]) as sim:
        while not sim.finished():
            sim.advance(1000)                  # steps, never past the scene's end
        sim.scalar("stress")                   # the last series row's value, Pa
        sim.summary()["apparent_young"]        # summary.json's keys, as a dict

Every failure raises FractumError with the library's status and its one-sentence message.
"""

import ctypes
import json
import operator
import os

import numpy as np

__all__ = ["Simulation", "FractumError", "ModelError", "version", "load_library"]

_STATUS = {
    0: "FRACTUM_OK",
    1: "FRACTUM_ERR_NULL",
    2: "FRACTUM_ERR_HANDLE",
    3: "FRACTUM_ERR_INPUT",
    4: "FRACTUM_ERR_RUN",
    5: "FRACTUM_ERR_BUFFER",
    6: "FRACTUM_ERR_INTERNAL",
    7: "FRACTUM_ERR_MODEL",
    8: "FRACTUM_INTERRUPTED",
}

_ERR_BUFFER = 5
_INTERRUPTED = 8
_ERR_MODEL = 7


class FractumError(RuntimeError):
    """A call into libfractum failed: `status` names the status code, `message` says why."""

    def __init__(self, status, message):
        self.status = _STATUS.get(status, str(status))
        self.message = message
        super().__init__("%s: %s" % (self.status, message))


class ModelError(FractumError):
    """The call does not apply to this run's model (FRACTUM_ERR_MODEL): the SHPB face calls
    and radii on a dlsm or beam2d run, or on a granular one without a box. Nothing changed."""


class Interrupted(FractumError):
    """An advance call stopped early, before a step, because a bound of `set_call_limits` ran
    out or `cancel` was called (FRACTUM_INTERRUPTED). The run is consistent: call again to go
    on."""


_lib = None


def load_library(path=None):
    """Loads libfractum.so (once) and declares its functions."""
    global _lib
    if _lib is not None and path is None:
        return _lib
    candidates = [path, os.environ.get("FRACTUM_LIB")]
    here = os.path.dirname(os.path.abspath(__file__))
    # Installed (`pip install ./ffi/python`): the library built into the package.
    candidates.append(os.path.join(here, "libfractum.so"))
    # From the repository (ffi/python on sys.path): its release build.
    candidates.append(os.path.join(here, "..", "..", "..", "target", "release", "libfractum.so"))
    candidates.append("libfractum.so")
    last = None
    for c in candidates:
        if not c:
            continue
        try:
            lib = ctypes.CDLL(c)
            break
        except OSError as e:
            last = e
    else:
        raise OSError("libfractum.so not found (set FRACTUM_LIB): %s" % last)
    d, u64, sz, p = ctypes.c_double, ctypes.c_uint64, ctypes.c_size_t, ctypes.POINTER
    st = ctypes.c_int
    buf = p(ctypes.c_char)
    sigs = {
        "fractum_create_from_file": [ctypes.c_char_p, p(ctypes.c_char_p), sz, ctypes.c_int32, p(u64)],
        "fractum_create_from_text": [ctypes.c_char_p, ctypes.c_char_p, p(ctypes.c_char_p), sz, ctypes.c_int32, p(u64)],
        "fractum_free": [u64],
        "fractum_model": [u64, p(ctypes.c_char_p)],
        "fractum_advance": [u64, u64],
        "fractum_advance_to": [u64, d],
        "fractum_finished": [u64, p(ctypes.c_int32)],
        "fractum_time": [u64, p(d)],
        "fractum_steps": [u64, p(u64)],
        "fractum_dt": [u64, p(d)],
        "fractum_bodies": [u64, p(u64)],
        "fractum_set_face_speeds": [u64, d, d],
        "fractum_face_forces": [u64, p(d), p(d)],
        "fractum_face_stresses": [u64, p(d), p(d), p(d)],
        "fractum_progress": [u64, p(d), p(d), p(u64)],
        "fractum_counts": [u64, p(u64), p(u64), p(d)],
        "fractum_scalar": [u64, ctypes.c_char_p, p(d)],
        "fractum_columns": [u64, buf, sz, p(sz)],
        "fractum_summary_json": [u64, buf, sz, p(sz)],
        "fractum_copy_positions": [u64, p(d), sz],
        "fractum_copy_velocities": [u64, p(d), sz],
        "fractum_copy_orientations": [u64, p(d), sz],
        "fractum_copy_radii": [u64, p(d), sz],
        "fractum_state_size": [u64, p(sz)],
        "fractum_save_state": [u64, p(ctypes.c_uint8), sz, p(sz)],
        "fractum_restore_state": [u64, p(ctypes.c_uint8), sz],
        "fractum_reset": [u64],
        "fractum_set_call_limits": [u64, u64, d],
        "fractum_cancel": [u64],
    }
    for name, args in sigs.items():
        f = getattr(lib, name)
        f.argtypes = args
        f.restype = st
    lib.fractum_version.argtypes = []
    lib.fractum_version.restype = ctypes.c_char_p
    lib.fractum_last_error.argtypes = []
    lib.fractum_last_error.restype = ctypes.c_char_p
    _lib = lib
    return lib


def _check(status):
    if status != 0:
        message = load_library().fractum_last_error().decode("utf-8", "replace")
        kind = {_ERR_MODEL: ModelError, _INTERRUPTED: Interrupted}.get(status, FractumError)
        raise kind(status, message)


def version():
    """The library's version string."""
    return load_library().fractum_version().decode()


def _strings(items):
    items = [s.encode() for s in items]
    return (ctypes.c_char_p * max(len(items), 1))(*items), len(items)


def _count(name, value):
    """`value` as a count for a uint64_t argument. int() turned -1 into 2^64 - 1 steps (ctypes
    wraps it) and 1.5 into 1; a count must be a whole number (int or numpy integer) in
    [0, 2^64 - 1]."""
    if isinstance(value, bool):
        raise TypeError(f"{name} must be a whole number of steps, not {value!r}")
    try:
        n = operator.index(value)
    except TypeError:
        raise TypeError(f"{name} must be a whole number of steps, not {value!r}") from None
    if not 0 <= n < 2**64:
        raise ValueError(f"{name} = {n} is outside the allowed range [0, 2^64 - 1]")
    return n


def _check_threads(threads):
    """threads as the C ABI's int32_t: 0 (every core) up to the machine's cores, which the
    library checks. ctypes fills the int by wrapping: 2**40 became 0 (every core), 2**32 + 1
    became 1 and -1 was taken as every core."""
    cores = os.cpu_count() or 1
    if isinstance(threads, bool):
        raise TypeError(f"threads must be a whole number, not {threads!r}")
    try:
        n = operator.index(threads)
    except TypeError:
        raise TypeError(f"threads must be a whole number, not {threads!r}") from None
    if not 0 <= n < 2**31:
        raise ValueError(f"threads = {n} is outside the allowed range [0, {cores}] "
                         "(0: every core)")
    return n


def _check_no_nul(what, value):
    if value is None:
        return
    text = os.fsdecode(value) if isinstance(value, (bytes, os.PathLike)) else str(value)
    if "\0" in text:
        raise ValueError("%s holds a NUL character at offset %d: a scene, path or override "
                         "cannot hold one" % (what, text.index("\0")))


class Simulation:
    """One simulation inside libfractum. Use it as a context manager, or call close()."""

    def __init__(self, scene=None, text=None, base_dir=None, overrides=(), threads=1):
        lib = load_library()
        if (scene is None) == (text is None):
            raise ValueError("give exactly one of scene (a path) or text (TOML)")
        threads = _check_threads(threads)
        # A C string ends at its first NUL: the rest of a text or path was cut off silently.
        for what, value in [("text", text), ("scene", scene), ("base_dir", base_dir)] + [
                ("overrides[%d]" % k, o) for k, o in enumerate(overrides)]:
            _check_no_nul(what, value)
        arr, n = _strings(list(overrides))
        handle = ctypes.c_uint64(0)
        if scene is not None:
            _check(lib.fractum_create_from_file(os.fsencode(scene), arr, n, threads, ctypes.byref(handle)))
        else:
            base = os.fsencode(base_dir) if base_dir is not None else None
            _check(lib.fractum_create_from_text(text.encode(), base, arr, n, threads, ctypes.byref(handle)))
        self._h = handle.value

    def close(self):
        """Frees the simulation; further calls raise FractumError (FRACTUM_ERR_HANDLE)."""
        if self._h:
            h, self._h = self._h, 0
            _check(load_library().fractum_free(h))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    @property
    def handle(self):
        return self._h

    def _call(self, name, *args):
        _check(getattr(load_library(), name)(self._h, *args))

    def _get(self, name, ctype):
        v = ctype()
        self._call(name, ctypes.byref(v))
        return v.value

    def _text(self, name):
        """A text answer: asks for its size, then fetches it."""
        lib = load_library()
        needed = ctypes.c_size_t()
        status = getattr(lib, name)(self._h, None, 0, ctypes.byref(needed))
        if status != _ERR_BUFFER:
            _check(status)
        buf = ctypes.create_string_buffer(needed.value)
        self._call(name, buf, needed.value, ctypes.byref(needed))
        return buf.value.decode("utf-8")

    @property
    def model(self):
        """The scene's model: "granular", "dlsm" or "beam2d"."""
        return self._get("fractum_model", ctypes.c_char_p).decode()

    def advance(self, steps):
        """Takes up to `steps` steps of the run's own time step, never past the scene's end."""
        self._call("fractum_advance", _count("steps", steps))

    def advance_to(self, time):
        """Advances to exactly `time` (s). beam2d with Gear5 takes whole steps only and
        refuses a time between them (FractumError, FRACTUM_ERR_RUN)."""
        self._call("fractum_advance_to", float(time))

    def set_call_limits(self, max_steps=0, max_seconds=0.0):
        """Bounds each later advance call: it raises Interrupted, before a step, once it has
        taken `max_steps` steps or run `max_seconds` of wall time (0: no bound)."""
        self._call("fractum_set_call_limits", _count("max_steps", max_steps), float(max_seconds))

    def cancel(self):
        """Stops the advance call in progress in another thread (or else the next one) before
        its next step: that call raises Interrupted. Does not wait."""
        self._call("fractum_cancel")

    def finished(self):
        """True once the run has reached the scene's end (or the model stopped it)."""
        return bool(self._get("fractum_finished", ctypes.c_int32))

    def time(self):
        """The time (s)."""
        return self._get("fractum_time", ctypes.c_double)

    def steps(self):
        """The number of steps taken."""
        return self._get("fractum_steps", ctypes.c_uint64)

    def dt(self):
        """The time step (s)."""
        return self._get("fractum_dt", ctypes.c_double)

    def bodies(self):
        """The number of bodies (particles, elements or polygons); grains break, so it grows."""
        return self._get("fractum_bodies", ctypes.c_uint64)

    def scalar(self, name):
        """The series column `name` (see columns()) in the last recorded row (rows come every
        output.every steps and at the end). An unknown name raises FRACTUM_ERR_INPUT."""
        v = ctypes.c_double()
        self._call("fractum_scalar", name.encode(), ctypes.byref(v))
        return v.value

    def columns(self):
        """The series columns, as in series.csv."""
        return self._text("fractum_columns").split(",")

    def summary(self):
        """The results so far as a dict: summary.json's keys but wall_seconds."""
        return json.loads(self._text("fractum_summary_json"))

    def set_face_speeds(self, top, bottom):
        """Top (z+) and bottom (z-) faces move into the sample at these speeds (m/s).
        Granular samples in a box only (else ModelError)."""
        self._call("fractum_set_face_speeds", float(top), float(bottom))

    def face_forces(self):
        """Compressive normal forces (N) on the top and bottom faces (granular box only)."""
        t, b = ctypes.c_double(), ctypes.c_double()
        self._call("fractum_face_forces", ctypes.byref(t), ctypes.byref(b))
        return t.value, b.value

    def face_stresses(self):
        """Compressive normal stresses (Pa) on the top and bottom faces, and their area (m^2)
        (granular box only)."""
        t, b, a = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
        self._call("fractum_face_stresses", ctypes.byref(t), ctypes.byref(b), ctypes.byref(a))
        return t.value, b.value, a.value

    def progress(self):
        """(time in s, axial strain of a granular box (NaN for other models), steps taken)."""
        t, s, n = ctypes.c_double(), ctypes.c_double(), ctypes.c_uint64()
        self._call("fractum_progress", ctypes.byref(t), ctypes.byref(s), ctypes.byref(n))
        return t.value, s.value, n.value

    def counts(self):
        """(bodies, body-body contacts, kinetic energy in J); models other than granular give
        the contacts and kinetic energy of the last series row (0 and NaN if not recorded)."""
        b, c, k = ctypes.c_uint64(), ctypes.c_uint64(), ctypes.c_double()
        self._call("fractum_counts", ctypes.byref(b), ctypes.byref(c), ctypes.byref(k))
        return b.value, c.value, k.value

    def _array(self, name, per_body):
        n = self.bodies()
        out = np.empty(n * per_body, dtype=np.float64)
        self._call(name, out.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), out.size)
        return out.reshape(n, per_body) if per_body > 1 else out

    def positions(self):
        """Centres (m) as an (n, 3) array (z = 0 for beam2d)."""
        return self._array("fractum_copy_positions", 3)

    def velocities(self):
        """Velocities (m/s) as an (n, 3) array."""
        return self._array("fractum_copy_velocities", 3)

    def orientations(self):
        """Unit quaternions (w, x, y, z) as an (n, 4) array; beam2d turns about z only."""
        return self._array("fractum_copy_orientations", 4)

    def radii(self):
        """Radii (m) as an (n,) array (granular only, else ModelError)."""
        return self._array("fractum_copy_radii", 1)

    def grain_loads(self):
        """Each grain's load at the last fracture check, as an (n, 22) array: columns 0-8 the
        moment of its contact forces about its centre (N m, row-major), 9 the number of
        critical contacts, 10-12 the three largest contact tensile stresses (Pa) and 13-21
        their points (m), largest first, zeros past the count. Zeros for grains held by
        intact springs, for halves made at that check and before the first step. Granular
        runs with the "fracture" effect only, else ModelError."""
        return self._array("fractum_copy_grain_loads", 22)

    def save_state(self):
        """The whole state as bytes."""
        size = ctypes.c_size_t()
        self._call("fractum_state_size", ctypes.byref(size))
        buf = (ctypes.c_uint8 * size.value)()
        written = ctypes.c_size_t()
        self._call("fractum_save_state", buf, size.value, ctypes.byref(written))
        return bytes(buf[: written.value])

    def restore_state(self, state):
        """Restores bytes from save_state(); the run then continues bit for bit."""
        buf = (ctypes.c_uint8 * len(state)).from_buffer_copy(state)
        self._call("fractum_restore_state", buf, len(state))

    def reset(self):
        """Back to the state right after creation."""
        self._call("fractum_reset")
