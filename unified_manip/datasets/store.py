"""Datasets on disk: where one lives, how it is published whole, and how it is opened.

A dataset is Minari's directory ``ROOT/NAME-vN/data/`` (``main_data.hdf5`` and
``metadata.json``), so ``MINARI_DATASETS_PATH=ROOT`` and ``minari.load_dataset("NAME-vN")``
read it. It is written under a hidden temporary name beside it and renamed into place
once complete: an interrupted ``collect`` or ``convert`` leaves no directory that reads as
a dataset. What this project adds sits in the metadata under :data:`KEY`.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
from pathlib import Path
from typing import Any, Iterator

from unified_manip.datasets import versions
from unified_manip.datasets.errors import DatasetError

#: The metadata entry that holds what this project records (see :mod:`.recording`).
KEY = "unified_manip"

#: What ``infos/state`` holds (the backends' ``get_state``).
STATE = "mj_getState(model, data, state, mjSTATE_FULLPHYSICS)"

#: The ``minari_version`` every dataset declares: the oldest supported Minari release.
#: Minari writes its own release there and refuses a dataset of a release it does not
#: know (0.5.3 refuses 0.5.4's), but 0.5.4 writes 0.5.3's HDF5 layout: it only adds a
#: ``jpeg_encoding`` switch, on by default, as 0.5.3 always encodes images. Declaring
#: 0.5.3 lets every supported release (``minari>=0.5.3,<0.6``) read every dataset; the
#: release that wrote it stays in this project's metadata (``versions``).
MINARI_FORMAT = "0.5.3"

_NAME = re.compile(r"^[A-Za-z0-9_.]+(-[A-Za-z0-9_.]+)*-v\d+$")


def check_out(out: Path, overwrite: bool) -> Path:
    """``out`` as a dataset path to write: its name ``NAME-vN`` (Minari's dataset ID), and
    no dataset there unless ``overwrite``."""
    out = Path(out)
    if not _NAME.match(out.name):
        raise DatasetError(f"--out must end in a dataset name NAME-vN (Minari's ID), e.g. data/arm4-pick-v0; got {out}")
    if out.exists() and not overwrite:
        raise DatasetError(f"{out} already exists; pass --overwrite to replace it")
    return out


@contextlib.contextmanager
def _datasets_root(root: Path) -> Iterator[None]:
    previous = os.environ.get("MINARI_DATASETS_PATH")
    os.environ["MINARI_DATASETS_PATH"] = str(root)
    try:
        yield
    finally:
        if previous is None:
            del os.environ["MINARI_DATASETS_PATH"]
        else:
            os.environ["MINARI_DATASETS_PATH"] = previous


def publish(out: Path, episodes: list, env: Any, metadata: dict[str, Any], description: str) -> None:
    """Write ``episodes`` (:class:`~.episodes.Episode` s) as the dataset ``out`` with Minari's
    ``create_dataset_from_buffers`` under a temporary name, add ``metadata`` (with the
    package versions and the state's definition) under :data:`KEY`, then rename it into
    place (replacing a dataset there). Nothing is left behind if it fails or is
    interrupted."""
    import minari

    metadata = {**metadata, "versions": versions.installed(), "state": STATE}
    buffers = [episode.buffer(i) for i, episode in enumerate(episodes)]
    out = Path(out).absolute()  # Minari joins a relative MINARI_DATASETS_PATH onto its own paths twice
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp_root = out.parent / f".{out.name}.partial-{os.getpid()}"
    shutil.rmtree(tmp_root, ignore_errors=True)
    trash = out.parent / f".{out.name}.old-{os.getpid()}"
    try:
        with _datasets_root(tmp_root):
            dataset = minari.create_dataset_from_buffers(
                dataset_id=out.name,
                buffer=buffers,
                env=env,
                eval_env=env,
                algorithm_name=metadata["policy"],
                author="unified_manip",
                author_email="https://github.com/unified-manip",
                code_permalink="https://github.com/unified-manip/unified_manip",
                description=description,
                requirements=versions.requirements(metadata["versions"]),
            )
            dataset.storage.update_metadata({KEY: metadata})
            _declare_format(tmp_root / out.name / "data" / "metadata.json")
        if out.exists():
            os.replace(out, trash)
        os.replace(tmp_root / out.name, out)
    finally:
        shutil.rmtree(tmp_root, ignore_errors=True)
        shutil.rmtree(trash, ignore_errors=True)


def _declare_format(path: Path) -> None:
    """Set the ``minari_version`` of the metadata file at ``path`` to :data:`MINARI_FORMAT`
    (Minari's ``update_metadata`` refuses to change it)."""
    meta = json.loads(path.read_text())
    meta["minari_version"] = MINARI_FORMAT
    path.write_text(json.dumps(meta))


def open_dataset(path: Path):
    """The ``MinariDataset`` at ``path`` (a dataset directory, as ``--out`` wrote it), with
    a one-line :class:`DatasetError` for a path that is not one of this project's
    datasets or whose HDF5 file is truncated or corrupted (every episode is opened)."""
    import h5py
    import minari

    path = Path(path)
    data = path / "data"
    if not (data / "metadata.json").is_file():
        raise DatasetError(f"{path} is not a dataset: expected a directory written by unified-manip collect or convert")
    try:
        dataset = minari.MinariDataset(data)
    except Exception as err:  # Minari raises several kinds for a bad metadata file
        raise DatasetError(f"{path} is not a readable dataset: {_one_line(err)}") from None
    if KEY not in dataset.storage.metadata and "combined_datasets" in dataset.storage.metadata:
        raise DatasetError(
            f"{path} was made by minari.combine_datasets, which keeps neither each episode's reset seed nor "
            f"unified_manip's {KEY!r} metadata, so its episodes cannot be replayed or converted; record them "
            "into one dataset with a single collect (--episodes N) instead"
        )
    if KEY not in dataset.storage.metadata:
        raise DatasetError(f"{path} is a Minari dataset but not one of unified_manip's (no {KEY!r} metadata)")
    try:
        with h5py.File(data / "main_data.hdf5", "r") as file:
            for i in range(dataset.total_episodes):
                for name in ("actions", "rewards", "observations", "infos"):
                    _touch(file[f"episode_{i}/{name}"])
    except (OSError, KeyError, RuntimeError, ValueError) as err:
        raise DatasetError(f"{path}: its HDF5 file is truncated or corrupted ({_one_line(err)})") from None
    return dataset


def metadata(dataset) -> dict[str, Any]:
    """What this project recorded about ``dataset`` (:data:`KEY`)."""
    return dataset.storage.metadata[KEY]


def _touch(node) -> None:
    import h5py

    if isinstance(node, h5py.Dataset):
        node[()]  # reads every chunk: a truncated or corrupted one raises here
    else:
        for child in node.values():
            _touch(child)


def _one_line(err: BaseException) -> str:
    return " ".join(str(err).split()) or type(err).__name__
