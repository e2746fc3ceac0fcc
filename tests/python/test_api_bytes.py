"""The module's results are the CLI's files, bit for bit, on the committed meshes."""
import numpy as np
import pytest
from PIL import Image

import octrace
from conftest import json_file, npy_data


@pytest.fixture(scope="module")
def teapot_rays(teapot, teapot_path, cli, tmp_path_factory):
    """octrace.rays and `octrace rays` with the same spec, and the file paths."""
    d = tmp_path_factory.mktemp("rays")
    cli("rays", teapot_path, "--count", 4000, "--seed", 7, "--size", "48x32", "--out", d / "R.npy",
        "--triangles", d / "T.npy")
    with pytest.warns(UserWarning, match="slivers left out"):
        rays, manifest = octrace.rays(teapot, count=4000, seed=7, size=(48, 32))
    return rays, manifest, d


def test_rays_are_the_bytes_octrace_rays_writes(teapot, teapot_rays):
    rays, manifest, d = teapot_rays
    on_disk = npy_data(d / "R.npy")
    assert rays.dtype == np.float32 and rays.shape == on_disk.shape
    assert rays.tobytes() == on_disk.tobytes()
    assert manifest == json_file(d / "R.json")
    # scene.triangles is what --triangles writes: the triangles in primitive id order.
    assert teapot.triangles.reshape(-1, 9).tobytes() == npy_data(d / "T.npy").tobytes()


@pytest.mark.parametrize("layout", octrace.layouts())
def test_cast_rays_is_what_octrace_trace_writes(teapot, teapot_path, teapot_rays, cli, layout):
    rays, _, d = teapot_rays
    out = d / f"hits-{layout}"
    cli("trace", teapot_path, "--rays", d / "R.npy", "--out", out, "--accel", layout,
        "--backend", "cpu")
    got = teapot.cast_rays(rays, layout=layout, backend="cpu")
    assert got["t_hit"].tobytes() == npy_data(f"{out}.t.npy").tobytes()
    assert got["primitive_ids"].tobytes() == npy_data(f"{out}.prim.npy").tobytes()
    hits = got["primitive_ids"] >= 0
    assert hits.any() and (~hits).any()
    # The cost is counted per ray: every ray tests the root box at least, a hit a primitive.
    assert got["boxes_tested"].dtype == np.uint32 and got["prims_tested"].dtype == np.uint32
    assert (got["prims_tested"][hits] > 0).all()


def test_embree_through_the_module_is_embree_through_trace(teapot, teapot_path, teapot_rays, cli):
    rays, _, d = teapot_rays
    cli("trace", teapot_path, "--rays", d / "R.npy", "--out", d / "embree", "--backend", "embree")
    got = teapot.cast_rays(rays, backend="embree")
    assert got["t_hit"].tobytes() == npy_data(d / "embree.t.npy").tobytes()
    assert got["primitive_ids"].tobytes() == npy_data(d / "embree.prim.npy").tobytes()
    assert "boxes_tested" not in got  # Embree counts no traversal cost


def test_six_column_rays_are_rays_from_zero_to_infinity(teapot, teapot_rays):
    rays, _, _ = teapot_rays
    full = rays.copy()
    full[:, 6] = 0.0
    full[:, 7] = np.inf
    a = teapot.cast_rays(np.ascontiguousarray(rays[:, :6]))
    b = teapot.cast_rays(full)
    assert a["t_hit"].tobytes() == b["t_hit"].tobytes()
    assert a["primitive_ids"].tobytes() == b["primitive_ids"].tobytes()


def test_a_strided_array_traces_as_its_contiguous_copy(teapot, teapot_rays):
    rays, _, _ = teapot_rays
    every_other = rays[::2]
    assert not every_other.flags["C_CONTIGUOUS"]
    a = teapot.cast_rays(every_other)
    b = teapot.cast_rays(np.ascontiguousarray(every_other))
    assert a["t_hit"].tobytes() == b["t_hit"].tobytes()


@pytest.mark.parametrize("layout", ["linear", "hash"])
def test_render_is_the_png_and_arrays_octrace_render_writes(teapot, teapot_path, cli, tmp_path,
                                                            layout):
    cli("render", teapot_path, "--size", "40x30", "--accel", layout, "--backend", "cpu",
        "--out", tmp_path / "f.png", "--depth", tmp_path / "t.npy", "--prim", tmp_path / "p.npy",
        "--cost", tmp_path / "c.npy")
    f = teapot.render(size=(40, 30), layout=layout, backend="cpu")
    assert f["image"].shape == (30, 40, 3) and f["image"].dtype == np.uint8
    png = np.asarray(Image.open(tmp_path / "f.png").convert("RGB"))
    assert np.array_equal(f["image"], png)
    assert f["t"].tobytes() == npy_data(tmp_path / "t.npy").tobytes()
    assert f["prim"].tobytes() == npy_data(tmp_path / "p.npy").tobytes()
    assert f["cost"].tobytes() == npy_data(tmp_path / "c.npy").tobytes()


def test_render_with_a_camera_of_ones_own(teapot, teapot_path, cli, tmp_path):
    cam = ["--eye", "30,20,40", "--target", "0,0,0", "--up", "0,1,0", "--fov", "30",
           "--light", "0,50,0"]
    cli("render", teapot_path, "--size", "32x32", *cam, "--out", tmp_path / "f.png")
    f = teapot.render(size=(32, 32), eye=(30, 20, 40), target=(0, 0, 0), up=(0, 1, 0), fov=30,
                      light=(0, 50, 0))
    assert np.array_equal(f["image"], np.asarray(Image.open(tmp_path / "f.png").convert("RGB")))


def test_explain_is_explain_json(teapot, teapot_path, cli, tmp_path):
    cli("explain", teapot_path, "--pixel", "20,12", "--size", "40x30", "--json", tmp_path / "e.json")
    explained = teapot.explain(pixel=(20, 12), size=(40, 30))
    assert explained == json_file(tmp_path / "e.json")
    assert (explained["format"], explained["version"]) == ("octrace-explain", 2)
    ray = "0,0,40,0,0,-1"
    cli("explain", teapot_path, "--ray", ray, "--json", tmp_path / "r.json")
    assert teapot.explain(ray=(0, 0, 40, 0, 0, -1)) == json_file(tmp_path / "r.json")


def without_timings(value):
    """The report without its clocks (every "..._seconds" key, at any depth)."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if not k.endswith("_seconds")}
    return value


def test_info_is_info_json(teapot, teapot_path, cli, tmp_path):
    cli("info", teapot_path, "--max-depth", "5", "--json", tmp_path / "i.json")
    scene = octrace.Scene(teapot_path, max_depth=5)
    info = scene.info()
    assert without_timings(info) == without_timings(json_file(tmp_path / "i.json"))
    assert (info["format"], info["version"]) == ("octrace-info-report", 1)


def test_a_scene_from_the_triangles_traces_as_the_file(teapot, teapot_rays):
    rays, _, _ = teapot_rays
    copy = octrace.Scene.from_triangles(np.array(teapot.triangles).reshape(-1, 9))
    assert len(copy) == len(teapot) and copy.kind == "triangles"
    a, b = copy.cast_rays(rays), teapot.cast_rays(rays)
    assert a["t_hit"].tobytes() == b["t_hit"].tobytes()
    assert a["primitive_ids"].tobytes() == b["primitive_ids"].tobytes()


def test_a_point_cloud_from_points_traces_as_the_xyz_file(cli, tmp_path):
    rng = np.random.default_rng(3)
    points = rng.uniform(-1, 1, size=(300, 3)).astype(np.float32)
    path = tmp_path / "cloud.xyz"
    np.savetxt(path, points, fmt="%.9g")
    from_file = octrace.Scene(str(path), radius=0.05)
    from_array = octrace.Scene.from_points(np.loadtxt(path, dtype=np.float32), radius=0.05)
    assert from_array.kind == "spheres" and len(from_array) == 300
    assert np.array_equal(from_array.spheres, from_file.spheres)
    with pytest.warns(UserWarning):
        rays, _ = octrace.rays(from_file, count=2000, size=(16, 16))
    a, b = from_array.cast_rays(rays), from_file.cast_rays(rays)
    assert a["t_hit"].tobytes() == b["t_hit"].tobytes()
