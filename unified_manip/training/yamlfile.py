"""Reading the project's YAML files (hyperparameters, grids, claims, run configs) strictly.

Every file is a mapping of plain YAML literals: anchors, aliases and merge keys
(``<<: *defaults``) are fine, explicit tags (``!!python/object``, ``!!str``, ``!custom``)
are refused, whatever a loader would make of them. Each problem is one line that names
the file and the line::

    baselines/sac.yaml:12: YAML tag '!!python/name:os.system' is not allowed; write plain literals
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml


class YamlFileError(ValueError):
    """A YAML file that cannot be read, is not a mapping or holds a tag (one line)."""


def _where(path: Path, mark) -> str:
    return f"{path}:{mark.line + 1}" if mark is not None else str(path)


def load_mapping(path: Path, what: str = "a mapping") -> dict[str, Any]:
    """The mapping in the YAML file ``path``.

    Args:
        path: The file.
        what: What the mapping is expected to hold, for the error message, e.g.
            ``"a mapping of task IDs"``.

    Raises:
        YamlFileError: the file is missing, is not valid YAML, holds a tag, or is not
            a mapping; the message names the file and line.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise YamlFileError(f"{path}: file not found; expected a YAML file holding {what}") from None
    except (OSError, UnicodeDecodeError) as err:
        raise YamlFileError(f"{path}: cannot be read ({err})") from None
    try:
        for event in yaml.parse(text, Loader=yaml.SafeLoader):
            tag = getattr(event, "tag", None)
            if tag is not None:
                raise YamlFileError(
                    f"{_where(path, event.start_mark)}: YAML tag {_short(tag)!r} is not allowed; write plain literals"
                )
        root = yaml.compose(text, Loader=yaml.SafeLoader)
        data = yaml.safe_load(text)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None) or getattr(err, "context_mark", None)
        problem = getattr(err, "problem", None) or str(err).splitlines()[0]
        raise YamlFileError(f"{_where(path, mark)}: not valid YAML ({problem})") from None
    if not isinstance(data, dict):
        kind = "an empty file" if data is None else f"a {type(data).__name__}"
        raise YamlFileError(
            f"{_where(path, root.start_mark if root is not None else None)}: expected {what}, got {kind}"
        )
    return data


def _short(tag: str) -> str:
    """``tag:yaml.org,2002:python/name:os.system`` written as in the file: ``!!python/name:os.system``."""
    prefix = "tag:yaml.org,2002:"
    return "!!" + tag[len(prefix) :] if tag.startswith(prefix) else tag


def key_line(path: Path, key: str) -> int | None:
    """The line (1-based) of top-level ``key`` in the YAML mapping ``path``, if present."""
    root = yaml.compose(Path(path).read_text(), Loader=yaml.SafeLoader)
    if isinstance(root, yaml.MappingNode):
        for k, _ in root.value:
            if k.value == key:
                return k.start_mark.line + 1
    return None
