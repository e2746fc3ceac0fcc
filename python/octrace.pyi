# Type stubs of the octrace module (python/module.cpp; docs/PYTHON.md). help(octrace.Scene.cast_rays)
# and the other docstrings say what each argument means; these give editors the types.
from os import PathLike
from typing import Any, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

Vec3 = Sequence[float]
Size = Tuple[int, int]

class Scene:
    def __init__(self, path: Union[str, PathLike], *, radius: Optional[float] = None,
                 max_depth: int = 7, max_prims: int = 8, hash_slots: int = 4,
                 linear_budget_mib: int = 4096, hash_budget_mib: int = 4096,
                 node_budget: int = 33554432) -> None: ...
    @staticmethod
    def from_triangles(triangles: npt.NDArray[np.float32], *, name: str = "<triangles>",
                       max_depth: int = 7, max_prims: int = 8, hash_slots: int = 4,
                       linear_budget_mib: int = 4096, hash_budget_mib: int = 4096,
                       node_budget: int = 33554432) -> "Scene": ...
    @staticmethod
    def from_points(points: npt.NDArray[np.float32], radius: Optional[float] = None, *,
                    name: str = "<points>", max_depth: int = 7, max_prims: int = 8,
                    hash_slots: int = 4, linear_budget_mib: int = 4096,
                    hash_budget_mib: int = 4096, node_budget: int = 33554432) -> "Scene": ...
    @property
    def name(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @property
    def bounds(self) -> Tuple[Tuple[float, float, float], Tuple[float, float, float]]: ...
    @property
    def triangles(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def spheres(self) -> Optional[npt.NDArray[np.float32]]: ...
    def __len__(self) -> int: ...
    def info(self) -> dict[str, Any]: ...
    def cast_rays(self, rays: npt.NDArray[np.float32], layout: str = "linear",
                  backend: str = "cpu", threads: Optional[int] = None) -> dict[str, Any]: ...
    def render(self, *, size: Size = (512, 512), layout: str = "linear", backend: str = "cpu",
               eye: Optional[Vec3] = None, target: Optional[Vec3] = None,
               up: Optional[Vec3] = None, fov: float = 45.0, light: Optional[Vec3] = None,
               threads: Optional[int] = None) -> dict[str, Any]: ...
    def explain(self, *, pixel: Optional[Tuple[int, int]] = None,
                ray: Optional[Sequence[float]] = None, layout: str = "linear",
                size: Size = (512, 512), eye: Optional[Vec3] = None,
                target: Optional[Vec3] = None, up: Optional[Vec3] = None, fov: float = 45.0,
                light: Optional[Vec3] = None) -> dict[str, Any]: ...

def rays(scene: Scene, *, sets: str = "all", count: int = 30000, seed: int = 1,
         size: Size = (256, 256), eye: Optional[Vec3] = None, target: Optional[Vec3] = None,
         up: Optional[Vec3] = None, fov: float = 45.0,
         light: Optional[Vec3] = None) -> Tuple[npt.NDArray[np.float32], dict[str, Any]]: ...

def certify(scene: Scene, rays: npt.NDArray[np.float32], t_hit: npt.NDArray[np.float32],
            primitive_ids: Optional[npt.NDArray[np.int32]] = None,
            manifest: Union[dict[str, Any], str, PathLike, None] = None, *,
            require: str = "all", query: str = "closest", t_tolerance: float = ...,
            edge_tolerance: float = ..., grazing_cos: float = ...,
            max_ambiguous_rate: float = ..., max_rechecks: Optional[int] = None,
            threads: Optional[int] = None) -> dict[str, Any]: ...

def layouts() -> list[str]: ...
def backends() -> list[str]: ...
