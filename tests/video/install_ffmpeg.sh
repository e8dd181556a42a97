#!/usr/bin/env bash
# Makes sure ffmpeg and ffprobe are on PATH for the movie tests (tests/cli_video.rs decodes the
# movies `render -o movie.mp4` and `encode` write). Installs Debian's ffmpeg package with
# apt-get when missing (as root; else it says the command and fails).
set -euo pipefail
if command -v ffmpeg >/dev/null && command -v ffprobe >/dev/null; then
    exit 0
fi
if [ "$(id -u)" = 0 ]; then
    echo "tests/video: installing ffmpeg (apt-get install -y ffmpeg)" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends ffmpeg >/dev/null
else
    echo "tests/video: the movie tests need ffmpeg and ffprobe: sudo apt-get install -y ffmpeg" >&2
    exit 1
fi
