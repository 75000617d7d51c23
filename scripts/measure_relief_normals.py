"""The normal maps reconstruct() returns, against the truth: on test_grid.py's bumps and egg crates
as reliefs (256 px, the light given), the block-grid ratio (shadecut.evaluation.grid_step_ratio) and
the mean angular error of result.normals; on a sphere and a torus as objects, the error of
result.normals and of the normals of result.depth (normals_from_depth), which an object does not use.

Run: PYTHONPATH=addon /usr/bin/python3 scripts/measure_relief_normals.py
(at two commits, in two worktrees, to compare builds).
"""

import numpy as np

import shadecut
from shadecut import synthetic
from shadecut.evaluation import grid_step_ratio

LIGHTS = ((0.6, 0.3, 1.0), (-0.5, 0.7, 1.0), (1.0, -0.2, 0.8))


def mean_error(normals: np.ndarray, truth: np.ndarray, mask: np.ndarray) -> float:
    cosine = np.clip(np.sum(normals * truth, axis=-1), -1.0, 1.0)
    return float(np.degrees(np.arccos(cosine))[mask].mean())


def main() -> None:
    for kind in ("bumps", "egg_crate"):
        for light in LIGHTS:
            scene = getattr(synthetic, kind)(light, 256)
            result = shadecut.reconstruct(scene.image, scene.light, scene="relief")
            whole = np.ones(scene.image.shape, bool)
            print(f"{kind} under {light}: grid {grid_step_ratio(result.normals):.3f} "
                  f"(truth {grid_step_ratio(scene.normals):.3f}), error {mean_error(result.normals, scene.normals, whole):.2f} deg")
    for name, scene in (("sphere", synthetic.sphere((1.0, 0.0, 1.0), 256)), ("torus", synthetic.torus((0.5, 0.5, 1.0), 256))):
        result = shadecut.reconstruct(scene.image, scene.light, scene.mask)
        from_depth = shadecut.normals_from_depth(result.depth, scene.mask)
        print(f"{name}: error {mean_error(result.normals, scene.normals, scene.mask):.2f} deg, "
              f"its depth's normals {mean_error(from_depth, scene.normals, scene.mask):.2f} deg")


if __name__ == "__main__":
    main()
