"""Several photographs under lamps near the subject (option light_distance): the same photographs read
as under distant lights and as under lamps at their distance, over the whole surface, its two opposite
quarter corners and its middle (mean angular error, degrees).

    PYTHONPATH=addon /usr/bin/python3 scripts/measure_near_lamps.py

The photographs are synthetic.lit_by_lamps's: Lambertian, albedo 1, lamps at slant 40 degrees around
the viewer, the first from the top, at 1, 2 and 4 frame widths from the frame's centre. The table in
docs/results.md ("Near lamps") is its output.
"""

from __future__ import annotations

import numpy as np

import shadecut
from shadecut import materials, synthetic

SIZE = 256
SLANT = 40.0


def parts(mask: np.ndarray) -> dict:
    rows, cols = mask.shape
    corners, middle = np.zeros_like(mask), np.zeros_like(mask)
    corners[: rows // 4, : cols // 4] = corners[-rows // 4 :, -cols // 4 :] = True
    middle[3 * rows // 8 : 5 * rows // 8, 3 * cols // 8 : 5 * cols // 8] = True
    inside = shadecut.erode_mask(mask, 2)
    return {"whole": inside, "corners": corners & inside, "middle": middle & inside}


def errors(scene, normals) -> list:
    error = np.degrees(np.arccos(np.clip((normals * scene.normals).sum(-1), -1.0, 1.0)))
    return [error[where].mean() for where in parts(scene.mask).values()]


def main() -> None:
    scenes = {"bump field": synthetic.bumps((0, 0, 1), size=SIZE),
              "sphere": synthetic.sphere((0, 0, 1), size=SIZE, radius_fraction=0.45)}
    print("| surface | lamps | distance (frame widths) | read as distant: whole / corners / middle "
          "| read as near: whole / corners / middle |")
    print("|---|---|---|---|---|")
    for name, scene in scenes.items():
        for count in (4, 8):
            lights = materials.lights_around(count, SLANT)
            for distance in (1.0, 2.0, 4.0):
                photographs = synthetic.lit_by_lamps(scene, lights, distance)
                distant = shadecut.reconstruct(photographs, lights, scene.mask)
                near = shadecut.reconstruct(photographs, lights, scene.mask, light_distance=distance)
                cells = [" / ".join(f"{e:.2f}" for e in errors(scene, result.normals)) for result in (distant, near)]
                print(f"| {name} | {count} | {distance:g} | {cells[0]} | {cells[1]} |")


if __name__ == "__main__":
    main()
