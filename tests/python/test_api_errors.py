"""Wrong input is a Python exception with octrace's one-line message, never a crash."""
import errno
import os

import numpy as np
import pytest

import octrace

BAD = os.path.join(os.environ.get("OCT_SOURCE_DIR", "."), "tests", "data", "bad")


def corpus():
    """tests/data/bad/manifest.txt: each file and what loading it must do."""
    with open(os.path.join(BAD, "manifest.txt"), encoding="utf-8") as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                name, expectation = line.split(maxsplit=1)
                yield name, expectation.strip()


@pytest.mark.parametrize("name,expectation", list(corpus()))
def test_the_bad_file_corpus_raises_or_loads_as_octrace_info_says(name, expectation):
    path = os.path.join(BAD, name)
    kind, _, detail = expectation.partition(":")
    if kind == "error":
        with pytest.raises(ValueError) as caught:
            octrace.Scene(path)
        message = str(caught.value)
        assert detail in message and "\n" not in message
        return
    scene = octrace.Scene(path)  # ok:key=N,...: loaded, each drop counted
    dropped = scene.info()["load"]["dropped"]
    for item in detail.split(","):
        key, _, count = item.partition("=")
        if key in dropped:
            assert dropped[key] == int(count), (key, dropped)


def test_a_missing_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError) as caught:
        octrace.Scene(tmp_path / "absent.obj")  # os.PathLike accepted
    assert caught.value.errno == errno.ENOENT
    assert "absent.obj" in str(caught.value) and "check the path" in str(caught.value)


def test_a_directory_is_an_os_error(tmp_path):
    with pytest.raises(IsADirectoryError):
        octrace.Scene(str(tmp_path))


def test_a_pipe_is_an_os_error_not_a_hang(tmp_path):
    fifo = tmp_path / "scene.obj"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match="not a regular file"):
        octrace.Scene(str(fifo))


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads a file of mode 000")
def test_an_unreadable_file_is_permission_error(tmp_path, teapot_path):
    path = tmp_path / "locked.obj"
    path.write_bytes(open(teapot_path, "rb").read())
    path.chmod(0)
    with pytest.raises(PermissionError):
        octrace.Scene(str(path))


@pytest.mark.parametrize("rays,match", [
    (np.zeros((4, 3), np.float32), r"\(4, 3\) float32"),
    (np.zeros((4, 8), np.float64), r"\(4, 8\) float64"),
    (np.zeros((4, 8), np.float16), "float16"),
    (np.zeros((4, 8), ">f4"), ">f4"),
    (np.zeros(8, np.float32), r"\(8,\) float32"),
    (np.zeros((2, 4, 8), np.float32), r"\(2, 4, 8\)"),
])
def test_rays_of_another_shape_or_dtype_are_value_errors(teapot, rays, match):
    with pytest.raises(ValueError, match=match) as caught:
        teapot.cast_rays(rays)
    assert "float32 (N, 8)" in str(caught.value)


def test_a_list_is_a_type_error(teapot):
    with pytest.raises(TypeError, match="numpy array"):
        teapot.cast_rays([[0, 0, 0, 0, 0, 1, 0, 1]])


def test_zero_rows_trace_to_empty_arrays(teapot):
    got = teapot.cast_rays(np.zeros((0, 8), np.float32))
    assert got["t_hit"].shape == (0,) and got["primitive_ids"].shape == (0,)


def test_zero_rows_are_nothing_to_certify(teapot):
    empty = np.zeros((0, 8), np.float32)
    with pytest.raises(ValueError, match="no rays"):
        octrace.certify(teapot, empty, np.zeros(0, np.float32))


def test_a_row_trace_refuses_is_named(teapot):
    rays = np.tile(np.array([0, 0, 40, 0, 0, -1, 0, np.inf], np.float32), (5, 1))
    rays[3, 5] = np.nan
    with pytest.raises(ValueError, match="row 3: direction"):
        teapot.cast_rays(rays)
    rays[3, 5] = -1
    rays[2, 6] = -1  # a negative tmin
    with pytest.raises(ValueError, match="row 2: tmin"):
        teapot.cast_rays(rays)


def test_hits_of_the_wrong_length_or_dtype(teapot):
    rays = np.tile(np.array([0, 0, 40, 0, 0, -1, 0, np.inf], np.float32), (5, 1))
    with pytest.raises(ValueError, match="one per ray"):
        octrace.certify(teapot, rays, np.zeros(4, np.float32))
    with pytest.raises(ValueError, match="float64"):
        octrace.certify(teapot, rays, np.zeros(5, np.float64))
    with pytest.raises(ValueError, match="int32"):
        octrace.certify(teapot, rays, np.zeros(5, np.float32), np.zeros(5, np.int64))


def test_bad_options_name_themselves(teapot, teapot_path):
    rays = np.zeros((1, 8), np.float32)
    with pytest.raises(ValueError, match="layout: unknown 'nope'"):
        teapot.cast_rays(rays, layout="nope")
    with pytest.raises(ValueError, match="backend: unknown 'gpu'"):
        teapot.cast_rays(rays, backend="gpu")
    with pytest.raises(ValueError, match="threads"):
        teapot.cast_rays(rays, threads=0)
    with pytest.raises(ValueError, match="max_depth"):
        octrace.Scene(teapot_path, max_depth=40)
    with pytest.raises(ValueError, match="radius"):
        octrace.Scene(teapot_path, radius=-1.0)
    with pytest.raises(ValueError, match="size"):
        teapot.render(size=(0, 10))
    with pytest.raises(ValueError, match="eye"):
        teapot.render(eye=(1, 2))
    with pytest.raises(ValueError, match="fov"):
        teapot.render(fov=180)
    with pytest.raises(ValueError, match="unknown set 'corners'"):
        octrace.rays(teapot, sets="corners")
    with pytest.raises(ValueError, match="slivers"):
        octrace.rays(teapot, sets="slivers")
    with pytest.raises(ValueError, match="pixel"):
        teapot.explain(pixel=(600, 0))
    with pytest.raises(ValueError, match="ray: "):
        teapot.explain(ray=(0, 0, 0, 0, 0, 0))


def test_arrays_a_loader_would_drop_from_are_refused_by_row():
    tri = np.array([[0, 0, 0, 1, 0, 0, 0, 1, 0]] * 3, np.float32)
    tri[1] = [0, 0, 0, 1, 1, 1, 2, 2, 2]  # zero area
    with pytest.raises(ValueError, match="row 1 of 3 is a triangle of zero area"):
        octrace.Scene.from_triangles(tri)
    tri[1] = tri[0]
    tri[2, 4] = np.inf
    with pytest.raises(ValueError, match="row 2 of 3 has a non-finite coordinate"):
        octrace.Scene.from_triangles(tri)
    with pytest.raises(ValueError, match="no triangles"):
        octrace.Scene.from_triangles(np.zeros((0, 9), np.float32))
    with pytest.raises(ValueError, match=r"\(M, 3, 3\)"):
        octrace.Scene.from_triangles(np.zeros((4, 3), np.float32))
    with pytest.raises(ValueError, match="no points"):
        octrace.Scene.from_points(np.zeros((0, 3), np.float32), 0.1)
    with pytest.raises(ValueError, match="radius"):
        octrace.Scene.from_points(np.zeros((2, 3), np.float32), float("nan"))


def test_a_malformed_manifest_is_a_value_error(teapot):
    rays = np.tile(np.array([0, 0, 40, 0, 0, -1, 0, np.inf], np.float32), (5, 1))
    t = np.full(5, np.inf, np.float32)
    with pytest.raises(ValueError, match="manifest"):
        octrace.certify(teapot, rays, t, manifest={"format": "nonsense"})
    with pytest.raises(FileNotFoundError):
        octrace.certify(teapot, rays, t, manifest="/nonexistent/R.json")


def test_a_bytes_path_is_a_path(teapot_path):
    assert len(octrace.Scene(os.fsencode(teapot_path))) == 992


def test_numbers_are_named_in_the_options_spelling(teapot):
    with pytest.raises(ValueError, match=r"count: -1 is not in"):
        octrace.rays(teapot, count=-1)
    with pytest.raises(ValueError, match=r"threads: 0 is not in \[1, "):
        teapot.cast_rays(np.zeros((1, 8), np.float32), threads=0)
    with pytest.raises(ValueError, match="fov: 200 must be"):
        teapot.render(fov=200)
    with pytest.raises(ValueError, match=r"pixel: \(9, 0\) is outside the 8x8 image"):
        teapot.explain(pixel=(9, 0), size=(8, 8))


def test_certify_refuses_rows_trace_refuses_instead_of_aborting(teapot):
    rays = np.tile(np.array([0, 0, 40, 0, 0, -1, 0, np.inf], np.float32), (4, 1))
    rays[1, 6] = -1  # a negative tmin: Embree, the reference, asserts on it
    with pytest.raises(ValueError, match="row 1: tmin"):
        octrace.certify(teapot, rays, np.full(4, np.inf, np.float32))


def test_a_view_too_large_to_copy_is_a_memory_error(teapot):
    from numpy.lib.stride_tricks import as_strided
    huge = as_strided(np.zeros(8, np.float32), shape=(2**40, 8), strides=(0, 4))
    with pytest.raises(MemoryError, match="rays"):
        teapot.cast_rays(huge)


def test_warnings_made_errors_raise_the_warning(teapot):
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match="slivers left out"):
            octrace.rays(teapot, count=100, size=(4, 4))


def test_an_array_that_went_through_pickle_is_accepted(teapot):
    import pickle
    rays = np.tile(np.array([0, 0, 40, 0, 0, -1, 0, np.inf], np.float32), (3, 1))
    again = pickle.loads(pickle.dumps(rays))
    assert teapot.cast_rays(again)["t_hit"].tobytes() == teapot.cast_rays(rays)["t_hit"].tobytes()


def test_paths_keep_their_bytes_and_refuse_a_null(teapot_path, tmp_path):
    odd = os.path.join(os.fsencode(str(tmp_path)), b"caf\xe9.obj")
    with open(odd, "wb") as f:
        f.write(open(teapot_path, "rb").read())
    assert len(octrace.Scene(odd)) == 992
    assert len(octrace.Scene(os.fsdecode(odd))) == 992
    with pytest.raises(ValueError, match="null byte"):
        octrace.Scene(teapot_path + "\0/other.obj")


def test_a_manifest_path_that_is_a_directory_is_an_os_error(teapot, tmp_path):
    rays = np.tile(np.array([0, 0, 40, 0, 0, -1, 0, np.inf], np.float32), (2, 1))
    with pytest.raises(IsADirectoryError):
        octrace.certify(teapot, rays, np.full(2, np.inf, np.float32), manifest=str(tmp_path))


def test_a_backend_that_cannot_run_here_is_a_runtime_error_saying_why(teapot):
    rays = np.tile(np.array([0, 0, 40, 0, 0, -1, 0, np.inf], np.float32), (2, 1))
    for name in octrace.backends():
        try:
            teapot.cast_rays(rays, backend=name)
        except RuntimeError as e:
            assert str(e).startswith(f"backend: '{name}' cannot run here: "), str(e)
