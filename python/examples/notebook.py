# %% [markdown]
# # filmsplat from Python: a real frame, its thickness, one particle's spectrum
#
# Runs as a script (`python notebook.py [OUTPUT_FOLDER]`) or cell by cell in Jupyter / VS Code.
# Loads the SPlisHSPlasH sphere shell from tests/data (12 394 particles, radius 0.025), gives it
# a draining film (thick at the bottom, thin at the top), renders it, shows the thickness with
# matplotlib and plots the reflectance spectrum R(λ) of one particle. matplotlib is optional:
# without it the example writes the renders only.

# %%
import os
import pathlib
import sys

import numpy as np

import filmsplat

here = pathlib.Path(__file__).resolve().parent
frame_path = here.parents[1] / "tests" / "data" / "splishsplash_sphere_shell.ply"
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
# The tests run it at 64x48 (FILMSPLAT_EXAMPLE_SIZE); the picture below is 480x360.
width, height = map(int, os.environ.get("FILMSPLAT_EXAMPLE_SIZE", "480x360").split("x"))
out.mkdir(parents=True, exist_ok=True)

frame = filmsplat.read(frame_path)
print(frame)

# %% [markdown]
# The file has positions and radii only. A film drains under gravity: thickness (nm) grows
# from ~150 nm at the top (y = +1) to ~900 nm at the bottom, plus a little swirl.

# %%
p = frame.positions
y = p[:, 1] / np.abs(p[:, 1]).max()
swirl = 60 * np.sin(6 * np.arctan2(p[:, 2], p[:, 0]) + 4 * y)
thickness_nm = 150 + 750 * ((1 - y) / 2) ** 1.5 + swirl
cloud = filmsplat.Cloud(p, radius=frame.radius, thickness_nm=thickness_nm)

scene = filmsplat.Scene(cloud, preset="balanced", width=width, height=height)
image = scene.render(progress=False)
image.save(out / "python_shell.png")
scene.render(view="thickness", progress=False).save(out / "python_shell_thickness.png")
print(scene, f"{image.rays} rays, built in {sum(scene.build_seconds.values()):.2f} s")

# %% [markdown]
# Thickness at the first film crossing of each pixel (nm), and R(λ) of the particle nearest
# the top of the shell, with numpy broadcasting over wavelengths and two angles.

# %%
top = int(np.argmax(p[:, 1]))
lam = np.linspace(380, 780, 201)
spectra = filmsplat.film(thickness_nm[top], np.array([[0.0], [60.0]]), lam)

try:
    import matplotlib

    matplotlib.use("Agg") if "ipykernel" not in sys.modules else None
    import matplotlib.pyplot as plt
except ImportError:
    plt = None
    print("matplotlib not installed: wrote the renders only")

if plt is not None:
    fig, ax = plt.subplots(1, 3, figsize=(15, 4), constrained_layout=True)
    ax[0].imshow(image.to_srgb8())
    ax[0].set_title("render (sRGB)")
    ax[0].axis("off")
    h = np.where(image.alpha > 0, image.layers["thickness"], np.nan)
    im = ax[1].imshow(h, cmap="viridis")
    fig.colorbar(im, ax=ax[1], label="film thickness at first crossing (nm)")
    ax[1].set_title("thickness view")
    ax[1].axis("off")
    for k, angle in enumerate((0, 60)):
        ax[2].plot(lam, spectra["R"][k], label=f"{angle}°")
    ax[2].set_xlabel("wavelength λ (nm)")
    ax[2].set_ylabel("reflectance R")
    ax[2].set_title(f"particle {top}: {thickness_nm[top]:.0f} nm film")
    ax[2].legend(title="incidence")
    fig.savefig(out / "python_example.png", dpi=80)
    print("wrote", out / "python_example.png")
