"""octrace.rays and `octrace rays` make the same rows and manifest from the same options, the
defaults included: issue 39 found octrace.rays() drawing its camera at render's 512x512 where the
CLI draws 256x256 (309,075 rows against 81,759). Both now read RaySetSpec's defaults
(validation/rays/ray_sets.h); this holds every option they share to the same bytes, one at a time.
(The scene's --radius is octrace.Scene's radius=, --triangles its .triangles: compared elsewhere.)
"""
import ast
import re
import warnings

import pytest

import octrace
from conftest import json_file, npy_data

MESH = "meshes/cube_binary.ply"  # closed: every set but slivers; 12 triangles, quick

# Over a small base, each option the two share set to a value other than its default.
BASE = {"count": 600, "size": (24, 16)}
CASES = {
    "defaults": {},  # no option at all, on either side
    "issue_39": {"sets": "all", "count": 6000, "seed": 41},
    "sets": {**BASE, "sets": "camera,edges,tmin-tmax"},
    "count": {**BASE, "count": 1234},
    "seed": {**BASE, "seed": 41},
    "size": {**BASE, "size": (40, 30)},
    "eye": {**BASE, "eye": (3.0, 2.0, 4.0)},
    "target": {**BASE, "target": (0.25, 0.5, 0.0)},
    "up": {**BASE, "up": (1.0, 1.0, 0.0)},
    "fov": {**BASE, "fov": 30.0},
    "light": {**BASE, "light": (5.0, -2.0, 3.0)},
}


def cli_args(options):
    """The command line spelling of octrace.rays' keywords."""
    args = []
    for key, value in options.items():
        if key == "size":
            value = f"{value[0]}x{value[1]}"
        elif isinstance(value, tuple):
            value = ",".join(repr(v) for v in value)
        args += ["--set" if key == "sets" else f"--{key}", value]
    return args


def test_every_keyword_has_a_case():
    # pybind11's signature line: rays(scene: octrace.Scene, *, sets: str = 'all', ...) -> tuple
    signature = octrace.rays.__doc__.splitlines()[0]
    keywords = re.findall(r"(\w+):", signature.split("*,")[1].split(") ->")[0])
    assert keywords and set(keywords) <= set(CASES), keywords


def test_the_type_stubs_state_the_modules_defaults(root):
    # python/octrace.pyi writes the defaults out for editors: a copy, held to the module's.
    signature = octrace.rays.__doc__.splitlines()[0].split("*,")[1].split(") ->")[0]
    module = {name: ast.literal_eval(value) for name, value in
              re.findall(r"(\w+): [\w\[\], .]+? = ('[^']*'|\([^)]*\)|[^,]+)", signature)}
    stub = next(f for f in ast.parse((root / "python" / "octrace.pyi").read_text()).body
                if isinstance(f, ast.FunctionDef) and f.name == "rays")
    stated = {a.arg: ast.literal_eval(d)
              for a, d in zip(stub.args.kwonlyargs, stub.args.kw_defaults)}
    assert module and stated == module


@pytest.mark.parametrize("case", CASES)
def test_module_and_cli_make_the_same_rays(root, cli, tmp_path, case):
    options = CASES[case]
    path = str(root / MESH)
    done = cli("rays", path, *cli_args(options), "--out", tmp_path / "R.npy")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rays, manifest = octrace.rays(octrace.Scene(path), **options)
    on_disk = npy_data(tmp_path / "R.npy")
    assert rays.shape == on_disk.shape, \
        f"{case}: {rays.shape[0]} rows, the CLI wrote {on_disk.shape[0]}"
    assert rays.tobytes() == on_disk.tobytes(), case
    assert manifest == json_file(tmp_path / "R.json"), case
    # What was left out or drawn again: the CLI's note lines, the module's warnings.
    notes = [line[len("note"):].strip()
             for line in done.stdout.splitlines() if line.startswith("note")]
    warned = [str(w.message)[len("octrace.rays: "):] for w in caught]
    assert warned == notes, case
