"""Stop 41: two .npz files of images (same_images.py, env_images.py) compared key by key: equal
bit for bit, or the largest difference and the relative MSE."""
import sys

import numpy as np

a, b = np.load(sys.argv[1]), np.load(sys.argv[2])
for k in a:
    x, y = a[k], b[k]
    rel = float(np.mean((x - y) ** 2) / max(np.mean(y ** 2), 1e-12))
    print(f"{k}: equal={np.array_equal(x, y)} max|diff|={np.abs(x - y).max():.3g} relMSE={rel:.3g}")
