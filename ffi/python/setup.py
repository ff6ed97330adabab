"""Builds libfractum.so with cargo (the repository's fractum-ffi crate, release profile) and puts
it inside the package, so that `pip install ./ffi/python` gives an `import fractum` that needs no
FRACTUM_LIB. Needs the Rust toolchain (cargo) and the repository around this folder."""
import os
import shutil
import subprocess

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))


class BuildWithLibrary(build_py):
    def run(self):
        if not os.path.exists(os.path.join(ROOT, "ffi", "Cargo.toml")):
            raise SystemExit(
                "fractum: the Rust sources are not at %s; install from a checkout of the "
                "repository (pip install ./ffi/python)" % ROOT
            )
        if shutil.which("cargo") is None:
            raise SystemExit("fractum: cargo (the Rust toolchain) is needed to build libfractum.so")
        subprocess.run(["cargo", "build", "--release", "-p", "fractum-ffi"], cwd=ROOT, check=True)
        target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
        built = os.path.join(target, "release", "libfractum.so")
        super().run()
        # Into the build tree only: a copy in the source tree would shadow the repository's
        # fresh build for code that puts ffi/python on sys.path.
        shutil.copyfile(built, os.path.join(self.build_lib, "fractum", "libfractum.so"))


setup(cmdclass={"build_py": BuildWithLibrary})
