"""Reference values for filmsplat's image metrics (src/image/metrics.rs).

Independent implementations: colour-science (CIELAB, CIEDE2000) and scikit-image (PSNR, SSIM).
Run: pip install colour-science scikit-image && python3 tests/data/metrics_reference.py
Writes tests/data/metrics_de2000.csv and tests/data/metrics_images.csv.
"""
import math
import os
import warnings

import numpy as np

warnings.filterwarnings("ignore")
import colour  # noqa: E402
from skimage.metrics import peak_signal_noise_ratio, structural_similarity  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
rng = np.random.default_rng(20261201)

# --- CIEDE2000 on Lab pairs: random, near-neutral and hue-wrap cases. ---
pairs = []
for _ in range(40):
    pairs.append((rng.uniform(0, 100), rng.uniform(-100, 100), rng.uniform(-100, 100),
                  rng.uniform(0, 100), rng.uniform(-100, 100), rng.uniform(-100, 100)))
for _ in range(10):  # small differences, the range that matters for renders
    l, a, b = rng.uniform(0, 100), rng.uniform(-60, 60), rng.uniform(-60, 60)
    pairs.append((l, a, b, l + rng.normal(0, 1), a + rng.normal(0, 1), b + rng.normal(0, 1)))
for h1, h2 in [(179.0, 181.0), (1.0, 359.0), (90.0, 271.0), (10.0, 200.0)]:  # hue wrap-around
    c = 30.0
    pairs.append((50.0, c * math.cos(math.radians(h1)), c * math.sin(math.radians(h1)),
                  55.0, c * math.cos(math.radians(h2)), c * math.sin(math.radians(h2))))
pairs.append((50.0, 0.0, 0.0, 50.0, 0.0, 0.0))
pairs.append((50.0, 0.0, 0.0, 50.0, 2.0, 0.0))
with open(os.path.join(HERE, "metrics_de2000.csv"), "w") as f:
    f.write("L1,a1,b1,L2,a2,b2,dE2000\n")
    for p in pairs:
        d = colour.delta_E(np.array(p[:3]), np.array(p[3:]), method="CIE 2000")
        f.write(",".join(f"{v:.12g}" for v in p) + f",{float(d):.12g}\n")

# --- Whole-image metrics on two formula images (the Rust test rebuilds them). ---
W, H = 24, 20
j, i = np.mgrid[0:H, 0:W].astype(np.float64)
def image(kind):
    chans = []
    for c in range(3):
        if kind == "a":
            v = 0.5 + 0.45 * np.sin(0.31 * i + 0.17 * j + 1.3 * c)
        else:
            v = 0.5 + 0.45 * np.sin(0.31 * i + 0.17 * j + 1.3 * c + 0.25) + 0.08 * np.cos(0.9 * i * j / 7.0 + c)
        chans.append(v * v)  # linear values, some above 1 are clipped
    return np.stack(chans, axis=-1)

def encode(lin):
    x = np.clip(lin, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)

a, b = image("a"), image("b")
ea, eb = encode(a), encode(b)
psnr = peak_signal_noise_ratio(ea, eb, data_range=1.0)
w709 = np.array([0.2126, 0.7152, 0.0722])
ssim = structural_similarity(ea @ w709, eb @ w709, gaussian_weights=True, sigma=1.5,
                             use_sample_covariance=False, data_range=1.0)
M = np.array([[0.4124564, 0.3575761, 0.1804375],
              [0.2126729, 0.7151522, 0.0721750],
              [0.0193339, 0.1191920, 0.9503041]])
white_xy = colour.XYZ_to_xy(np.array([0.95047, 1.0, 1.08883]))
lab_a = colour.XYZ_to_Lab(np.clip(a, 0, 1) @ M.T, white_xy)
lab_b = colour.XYZ_to_Lab(np.clip(b, 0, 1) @ M.T, white_xy)
de = colour.delta_E(lab_a, lab_b, method="CIE 2000").ravel()
with open(os.path.join(HERE, "metrics_images.csv"), "w") as f:
    f.write("psnr_db,ssim,de_mean,de_max\n")
    f.write(f"{psnr:.12g},{ssim:.12g},{de.mean():.12g},{de.max():.12g}\n")
print("psnr", psnr, "ssim", ssim, "dE mean", de.mean(), "max", de.max())
