"""Side-by-side figure (half size): render | before (main at 7de0f94) | sketch | colour pencil, one row per scene.
Usage: python3 compare.py DIR OUT.png  (DIR holds <scene>_{render,before,sketch,color_pencil}.png)"""
import sys

import matplotlib.image as mpimg
import numpy as np


def rgb(path):
    img = mpimg.imread(path)
    img = img[..., :3] if img.ndim == 3 else np.stack([img] * 3, -1)
    h, w = img.shape[0] // 2 * 2, img.shape[1] // 2 * 2
    # Half size (2x2 mean), so that the figure stays small; the full-size images lie beside it.
    return img[:h, :w].reshape(h // 2, 2, w // 2, 2, 3).mean(axis=(1, 3))


def main(folder, out):
    rows = []
    for scene in ("two_spheres", "watchtower"):
        tiles = [rgb(f"{folder}/{scene}_{kind}.png") for kind in ("render", "before", "sketch", "color_pencil")]
        gap = np.ones((tiles[0].shape[0], 4, 3))
        rows.append(np.concatenate(sum(([t, gap] for t in tiles), [])[:-1], 1))
    gap = np.ones((4, rows[0].shape[1], 3))
    mpimg.imsave(out, np.concatenate([rows[0], gap, rows[1]], 0))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
