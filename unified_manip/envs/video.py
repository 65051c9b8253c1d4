"""Rendered frames written as a video file, whole or not at all."""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: The video formats :func:`write_video` writes, by suffix.
VIDEO_SUFFIXES = (".mp4", ".gif")


def write_video(path: Path, frames: list[np.ndarray], fps: int) -> None:
    """Write ``frames`` to ``path``: MP4 (H.264, via imageio-ffmpeg) or GIF, chosen by its
    suffix. The file is written beside ``path`` under a temporary name and moved into place
    once complete, so an interrupted write leaves no partial video under ``path``.

    Raises:
        ValueError: ``path`` ends in neither ``.mp4`` nor ``.gif``.
    """
    import imageio.v3 as iio

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in VIDEO_SUFFIXES:
        raise ValueError(f"unsupported video format {path.suffix!r}; expected .mp4 or .gif")
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.partial{path.suffix}")
    try:
        if suffix == ".gif":
            iio.imwrite(tmp, np.stack(frames), duration=1000 / fps, loop=0)
        else:
            iio.imwrite(tmp, np.stack(frames), fps=fps, codec="libx264", macro_block_size=1)
        tmp.replace(path)
    finally:
        tmp.unlink(missing_ok=True)
