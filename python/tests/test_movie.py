"""filmsplat.movie: a sequence straight into a movie (ffmpeg on PATH; .ci/run installs it)."""

import os
import shutil
import subprocess

import pytest

import filmsplat


def _need_ffmpeg():
    missing = [p for p in ("ffmpeg", "ffprobe") if shutil.which(p) is None]
    assert not missing, (
        f"{missing} not found on PATH: the movie tests need ffmpeg "
        "(apt-get install ffmpeg, or run .ci/run, which installs it)"
    )


def _probe(path):
    out = subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
         "-show_entries", "stream=codec_name,pix_fmt,width,height,nb_read_frames,r_frame_rate",
         "-of", "default=noprint_wrappers=1", str(path)],
        check=True, capture_output=True, text=True,
    ).stdout
    return dict(line.split("=", 1) for line in out.split())


def _osc(tmp_path):
    scene = tmp_path / "osc.toml"
    scene.write_text('[input]\nsample = "oscillating-bubble"\nparticles = 3000\n')
    return scene


def test_movie_renders_a_sequence_with_progress(tmp_path, capfd):
    _need_ffmpeg()
    out = filmsplat.movie(
        _osc(tmp_path), tmp_path / "m.mp4", frames=range(0, 3), fps=12,
        size=(64, 48), preset="preview",
    )
    assert out == os.fspath(tmp_path / "m.mp4")
    info = _probe(out)
    assert info["codec_name"] == "h264" and info["pix_fmt"] == "yuv420p"
    assert (info["width"], info["height"], info["nb_read_frames"]) == ("64", "48", "3")
    assert info["r_frame_rate"] == "12/1"
    err = capfd.readouterr().err
    assert "frame 2 (3/3):" in err and "wrote 3 frames" in err
    # progress=False: no lines.
    filmsplat.movie(_osc(tmp_path), tmp_path / "q.webm", frames="0..2", size=(64, 48),
                    preset="preview", progress=False)
    assert _probe(tmp_path / "q.webm")["codec_name"] == "vp9"
    assert capfd.readouterr().err == ""


def test_movie_refuses_bad_input(tmp_path):
    with pytest.raises(ValueError, match=r"frames per second must be a number in \(0, 1000\]"):
        filmsplat.movie(_osc(tmp_path), tmp_path / "m.mp4", fps=0)
    with pytest.raises(ValueError, match="m.avi: -o must be images"):
        filmsplat.movie(_osc(tmp_path), tmp_path / "m.avi")
    with pytest.raises(ValueError, match="step 1"):
        filmsplat.movie(_osc(tmp_path), tmp_path / "m.mp4", frames=range(0, 10, 2))
    with pytest.raises(ValueError, match="render at --size 66x48"):
        filmsplat.movie(_osc(tmp_path), tmp_path / "m.mp4", size=(65, 48))
    assert not (tmp_path / "m.mp4").exists()
