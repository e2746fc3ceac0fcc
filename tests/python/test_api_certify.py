"""octrace.certify in process: the report and verdicts of `octrace certify`, and a corrupted hit caught."""
import numpy as np
import pytest

import octrace
from conftest import json_file, npy_data


@pytest.fixture(scope="module")
def traced(teapot):
    with pytest.warns(UserWarning):
        rays, manifest = octrace.rays(teapot, count=3000, size=(32, 32))
    hits = teapot.cast_rays(rays)
    return rays, manifest, hits["t_hit"], hits["primitive_ids"]


def corrupted(t, prim):
    """The hits with one hit's distance moved by a tenth of itself: a wrong answer."""
    t = t.copy()
    row = int(np.flatnonzero(prim >= 0)[17])
    t[row] *= 1.1
    return t, row


def test_octraces_own_hits_pass(teapot, traced):
    rays, manifest, t, prim = traced
    rep = octrace.certify(teapot, rays, t, prim, manifest)
    assert rep["pass"] is True and rep["outcome"] == "PASS"
    assert rep["hits"] == "t_hit, primitive_ids" and rep["baseline"] is None
    assert (rep["format"], rep["version"]) == ("octrace-certify-report", 1)
    assert rep["classes"].shape == (len(rays),) and rep["classes"].dtype == np.uint8
    assert not (rep["classes"] == 3).any()
    assert set(rep["result"]["sets"]) >= {"camera", "shadow", "edges", "vertices"}
    assert rep["result"]["by_set"]["edges"]["wrong"] == 0


def test_a_corrupted_hit_is_caught_and_selected_by_its_class(teapot, traced):
    rays, manifest, t, prim = traced
    bad, row = corrupted(t, prim)
    rep = octrace.certify(teapot, rays, bad, prim, manifest)
    assert rep["pass"] is False and rep["outcome"] == "FAIL"
    assert np.flatnonzero(rep["classes"] == 3).tolist() == [row]
    assert "FAIL" in rep["summary"]


def test_distances_only_and_without_a_manifest(teapot, traced):
    rays, _, t, prim = traced
    bad, row = corrupted(t, prim)
    rep = octrace.certify(teapot, rays, bad)  # no ids, no manifest: one set "all"
    assert rep["result"]["sets"] == ["all"]
    assert np.flatnonzero(rep["classes"] == 3).tolist() == [row]


def comparable(report):
    """A certify report without what differs between two runs of the same check: the clocks and
    the names of the files the CLI read (the module reads none)."""
    if isinstance(report, dict):
        return {k: comparable(v) for k, v in report.items()
                if not k.endswith("seconds") and k not in ("rays", "hits")}
    if isinstance(report, list):
        return [comparable(v) for v in report]
    return report


def test_the_report_and_verdicts_are_certifys(teapot, teapot_path, traced, cli, tmp_path):
    rays, manifest, t, prim = traced
    bad, _ = corrupted(t, prim)
    np.save(tmp_path / "R.npy", rays)
    (tmp_path / "R.json").write_text(__import__("json").dumps(manifest))
    np.save(tmp_path / "H.t.npy", bad)
    np.save(tmp_path / "H.prim.npy", prim)
    done = cli("certify", teapot_path, "--rays", tmp_path / "R.npy", "--hits", tmp_path / "H",
               "--json", tmp_path / "rep.json", "--verdicts", tmp_path / "V", check=False)
    assert done.returncode == 1, done.stderr  # FAIL
    rep = octrace.certify(teapot, rays, bad, prim, manifest)
    assert rep["classes"].tobytes() == npy_data(tmp_path / "V.class.npy").tobytes()
    assert rep["reasons"].tobytes() == npy_data(tmp_path / "V.reasons.npy").tobytes()
    assert rep["leak_states"].tobytes() == npy_data(tmp_path / "V.leak.npy").tobytes()
    ours = {k: v for k, v in rep.items()
            if k not in ("classes", "reasons", "leak_states", "outcome", "summary")}
    assert comparable(ours) == comparable(json_file(tmp_path / "rep.json"))
    # The manifest may be given as the path of R.json, as certify finds it beside R.npy.
    by_path = octrace.certify(teapot, rays, bad, prim, str(tmp_path / "R.json"))
    assert by_path["classes"].tobytes() == rep["classes"].tobytes()


def test_rays_of_another_scene_are_refused(traced, root):
    rays, manifest, t, prim = traced
    other = octrace.Scene(str(root / "meshes" / "cornell_box.obj"))
    with pytest.raises(ValueError, match="certify them against that scene"):
        octrace.certify(other, rays, t, prim, manifest)


def test_an_edited_row_is_refused_against_its_manifest(teapot, traced):
    rays, manifest, t, prim = traced
    edited = rays.copy()
    edited[5, 0] += 0.5
    with pytest.raises(ValueError, match="the rays were changed"):
        octrace.certify(teapot, edited, t, prim, manifest)


def test_policy_options_are_checked(teapot, traced):
    rays, manifest, t, prim = traced
    with pytest.raises(ValueError, match="t_tolerance"):
        octrace.certify(teapot, rays, t, prim, t_tolerance=2.0)
    with pytest.raises(ValueError, match="require"):
        octrace.certify(teapot, rays, t, prim, require="everything")
    with pytest.raises(ValueError, match="query"):
        octrace.certify(teapot, rays, t, prim, query="nearest")
