"""Fixtures of the Python suite: the repository, the octrace binary to compare with, and the module.

CTest runs each test file with PYTHONPATH=build/python, OCTRACE_BIN (the octrace binary of the same
build) and OCT_SOURCE_DIR (the repository) set (python/python.cmake); by hand:
    PYTHONPATH=build/python OCTRACE_BIN=build/octrace /usr/bin/python3 -m pytest tests/python
"""
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import octrace

ROOT = pathlib.Path(os.environ.get("OCT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def teapot_path():
    return str(ROOT / "meshes" / "teapot.obj")


@pytest.fixture(scope="session")
def teapot(teapot_path):
    return octrace.Scene(teapot_path)


def _binary():
    path = os.environ.get("OCTRACE_BIN", str(ROOT / "build" / "octrace"))
    if not os.access(path, os.X_OK):
        pytest.fail(f"no octrace binary at {path}: build it, or set OCTRACE_BIN")
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs `octrace ARGS...`; returns the completed process (check=True unless told)."""
    binary = _binary()

    def run(*args, check=True):
        done = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
        if check and done.returncode != 0:
            raise AssertionError(f"octrace {' '.join(map(str, args))} exited {done.returncode}:\n"
                                 f"{done.stdout}\n{done.stderr}")
        return done

    return run


def npy_data(path):
    """The data section of a .npy file: what the module's arrays must equal byte for byte."""
    return np.load(path, allow_pickle=False)


def json_file(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)
