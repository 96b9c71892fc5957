"""YAML loading and pydantic validation with file- and field-precise messages."""

from __future__ import annotations

import os
import re
from collections.abc import Hashable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import yaml
from pydantic import BaseModel, ConfigDict, ValidationError, ValidationInfo, field_validator
from pydantic_core import ErrorDetails

from ..errors import InputError
from ..paths import read_input_text

ModelT = TypeVar("ModelT", bound=BaseModel)


class StrictModel(BaseModel):
    """Base of every config model: unknown keys are errors, a boolean is never read as a number,
    and numbers are finite (YAML's .inf and .nan are refused)."""

    model_config = ConfigDict(
        extra="forbid", frozen=True, validate_default=True, allow_inf_nan=False
    )

    @field_validator("*", mode="before")
    @classmethod
    def _no_boolean_numbers(cls, value: Any, info: ValidationInfo) -> Any:
        if isinstance(value, bool) and info.field_name is not None:
            annotation = str(cls.model_fields[info.field_name].annotation)
            if "bool" not in annotation and ("float" in annotation or "int" in annotation):
                raise ValueError(f"expected a number, got the boolean {str(value).lower()}")
        return value


MAX_CONFIG_BYTES = 16 * 2**20
"""Largest config file read [bytes]: a study listing 100 000 records is about 10 MiB."""


class _Loader(getattr(yaml, "CSafeLoader", yaml.SafeLoader)):  # type: ignore[misc]
    """PyYAML's safe loader reading numbers as YAML 1.2 does, with duplicate keys refused.

    PyYAML implements YAML 1.1, where ``02500`` is octal (1344), ``1:00`` sexagesimal (60) and
    ``132.0e6`` or ``1e-3`` strings; here, as in YAML 1.2, integers are decimal (``0o`` and
    ``0x`` prefixes for the others), floats need no dot, and ``1:00`` is text. Duplicate keys are
    refused (YAML forbids them; PyYAML would keep the last one silently), merge keys (``<<:``)
    accepted, and ``!!set`` refused (it has no order). Its parser is libyaml's where PyYAML has
    it (every wheel does): a study listing 3000 records loads in 0.2 s instead of 2 s."""

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":  # merged keys may be overridden
                continue
            key = self.construct_object(key_node, deep=deep)
            if not isinstance(key, Hashable):
                raise yaml.constructor.ConstructorError(
                    None, None, "a key must be a plain value, not a list or a mapping",
                    key_node.start_mark,
                )  # fmt: skip
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None, None, f"duplicate key {key!r}", key_node.start_mark
                )
            seen.add(key)
        return super().construct_mapping(node, deep=deep)

    def construct_yaml_int(self, node) -> int:
        text = self.construct_scalar(node).replace("_", "")
        digits = text.lstrip("+-")
        base = {"0o": 8, "0x": 16}.get(digits[:2], 10)
        value = int(digits[2:] if base != 10 else digits, base)
        return -value if text.startswith("-") else value

    def construct_yaml_set(self, node):
        raise yaml.constructor.ConstructorError(
            None, None, "!!set is not supported (it has no order): use a list", node.start_mark
        )


_NUMBERS = ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float")
_Loader.yaml_implicit_resolvers = {  # YAML 1.1's numbers out; YAML 1.2's in, below
    first: [(tag, pattern) for tag, pattern in resolvers if tag not in _NUMBERS]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:int",
    re.compile(r"^(?:[-+]?[0-9][0-9_]*|0o[0-7_]+|0x[0-9a-fA-F_]+)$"),
    list("-+0123456789"),
)
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(
        r"""^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
        |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
        |[-+]?\.[0-9_]+(?:[eE][-+]?[0-9]+)?
        |[-+]?\.(?:inf|Inf|INF)
        |\.(?:nan|NaN|NAN))$""",
        re.X,
    ),
    list("-+0123456789."),
)
_Loader.add_constructor("tag:yaml.org,2002:int", _Loader.construct_yaml_int)
_Loader.add_constructor("tag:yaml.org,2002:set", _Loader.construct_yaml_set)


def read_yaml(path: str | Path) -> dict[str, Any]:
    """Read a YAML file that must hold a mapping.

    Raises
    ------
    InputError
        The file is missing, not a regular file, too large, unreadable, not valid YAML (duplicate
        keys included), nested too deeply, empty or not a mapping.
    """
    path = Path(path)
    text = read_input_text(path, MAX_CONFIG_BYTES, "a config file")
    try:
        data = yaml.load(text, Loader=_Loader)  # noqa: S506 (a SafeLoader subclass)
    except RecursionError:
        raise InputError(path, [("", "invalid YAML: nested too deeply")]) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        reason = getattr(exc, "problem", None) or str(exc)
        raise InputError(path, [(where, f"invalid YAML: {reason}")]) from None
    if data is None:
        raise InputError(path, [("", "the file is empty")])
    if not isinstance(data, dict):
        raise InputError(
            path, [("", f"expected a mapping of keys to values, got {type(data).__name__}")]
        )
    return data


def validate(model: type[ModelT], data: Any, source: str | Path, **context: Any) -> ModelT:
    """Validate ``data`` against ``model``, turning every pydantic error into an `InputError`.

    Parameters
    ----------
    model
        The pydantic model class.
    data
        The parsed YAML (or any mapping).
    source
        The file the data came from, named in the message.
    context
        Passed to the validators (for example the folder that relative paths are resolved against).
    """
    try:
        return model.model_validate(data, context=context or None)
    except ValidationError as exc:
        raise InputError(source, [_describe(err) for err in exc.errors()]) from None


def load(model: type[ModelT], path: str | Path, **context: Any) -> ModelT:
    """Read and validate a YAML config file; the paths inside it resolve against its folder and
    must lie where a config may reach (`ConfigFolder.of`)."""
    path = Path(path)
    folder = ConfigFolder.of(path)
    with reaching(folder):
        return validate(model, read_yaml(path), path, folder=folder, **context)


KIND_TAGS = ("=list", "=mapping")
"""Tags of the members of a config field that takes a list or a mapping (`kind_of`); a message
leaves them out of the field's path, which reads as the config is written."""


def kind_of(value: Any) -> str | None:
    """Which member of a list-or-mapping field ``value`` is for: `KIND_TAGS`, None for neither.

    The field's union is discriminated by it (pydantic's ``Discriminator``), so that a mistake
    is named once, for the kind given, instead of once for each member."""
    if isinstance(value, (list, tuple)):
        return KIND_TAGS[0]
    return KIND_TAGS[1] if isinstance(value, (dict, BaseModel)) else None


def _describe(error: ErrorDetails) -> tuple[str, str]:
    where = ".".join(str(part) for part in error["loc"] if part not in KIND_TAGS)
    reason = error["msg"].removeprefix("Value error, ")
    if error["type"] == "extra_forbidden":
        reason = "unknown key"
    elif isinstance(error.get("ctx", {}).get("error"), OutOfReach):
        pass  # the message names the path already
    elif error["type"] != "missing" and type(error.get("input")) in (str, int, float):
        reason = f"{reason} (got {_short(error['input'])})"
    return where, reason


def _short(value: Any, limit: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


ID_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$"
"""Bridge and record ids: they name HDF5 groups and files, so no slashes or spaces."""


PATHS_VARIABLE = "ROCKBRIDGE_PATHS"
"""Environment variable naming more folders (separated by ``os.pathsep``) whose files the paths
in a config may reach."""

PROJECT_MARKER = ".rockbridge"
"""The file that marks a project's root (`project_root`): the repository has one, so that its
bundled studies reach ``../../records`` from any working folder; ``touch .rockbridge`` marks a
user's own project."""


def project_root(config: Path) -> Path:
    """The root of the project the config file ``config`` lies in: the nearest folder, from the
    config's own (links followed) upwards, holding a `PROJECT_MARKER` file; the config's folder
    where there is none.

    A marker in the home folder or the file system's root is passed over: it would open every
    file of the user to any config handed over, which is what the confinement prevents.
    """
    folder = config.parent.resolve()
    try:
        too_wide = {Path(folder.anchor), Path.home().resolve()}
    except RuntimeError:  # no home folder
        too_wide = {Path(folder.anchor)}
    for candidate in (folder, *folder.parents):
        if candidate in too_wide:
            break
        if (candidate / PROJECT_MARKER).is_file():
            return candidate
    return folder


@dataclass(frozen=True)
class ConfigFolder:
    """Where a config's relative paths start, and the folders its paths may reach.

    A config names files (bridge files, records, record sets, seeds, its results file) by paths
    that resolve against its own folder. So that a config from elsewhere cannot make rockbridge
    read or write files far from it, those paths must lie in the config's project (the tree of
    the nearest folder above it marked by a `PROJECT_MARKER` file, else its own folder's tree),
    in the working folder's tree, or in a folder named in `PATHS_VARIABLE`, once every ``..``
    and symbolic link is followed (a link in the tree to a file outside it is refused too).
    Paths given on the command line are the user's own word and are not confined.

    Attributes
    ----------
    base
        The config's folder.
    reach
        The folders the config's paths may lie in (absolute, links followed); None: anywhere.
    refused
        The folders that would have let the refused paths through, for the message's way out
        (`reaching`).
    """

    base: Path
    reach: tuple[Path, ...] | None
    _reached: set[str] = field(default_factory=set, compare=False, repr=False)
    """The names already checked (a study may list a file thousands of times)."""
    refused: dict[Path, None] = field(default_factory=dict, compare=False, repr=False)

    @classmethod
    def of(cls, config: Path) -> ConfigFolder:
        """The folder of the config file ``config``, its paths confined as the class says."""
        named = [Path(f).expanduser() for f in os.environ.get(PATHS_VARIABLE, "").split(os.pathsep)]
        folders = (config.parent, project_root(config), Path.cwd(),
                   *(f for f in named if str(f) != "."))  # fmt: skip
        return cls(config.parent, tuple(dict.fromkeys(f.resolve() for f in folders)))

    def path(self, name: str | Path) -> Path:
        """``name``, a path in the config, against its folder.

        Raises
        ------
        ValueError
            The path lies outside the folders the config may reach.
        """
        path = self.base / name
        if self.reach is None or str(name) in self._reached:
            return path
        try:
            real = path.resolve()
        except (OSError, RuntimeError):  # a loop of symbolic links
            real = None
        if real is not None and any(real.is_relative_to(folder) for folder in self.reach):
            self._reached.add(str(name))
            return path
        if real is not None:
            self.refused[real if real.is_dir() else real.parent] = None
        leads = f", to {real}" if real is not None and str(real) != str(name) else ""
        raise OutOfReach(f"{name} leads outside the config's project and the working folder{leads}")


class OutOfReach(ValueError):
    """A path in a config that lies outside the folders the config may reach."""


@contextmanager
def reaching(folder: ConfigFolder) -> Iterator[None]:
    """Hand the folders that ``folder`` refused to the `InputError` raised inside, as its
    ``reach`` (the command line names them in the command that would work)."""
    try:
        yield
    except InputError as exc:
        exc.reach = tuple(dict.fromkeys((*exc.reach, *map(str, folder.refused))))
        raise


def resolve_path(path: Path, info: ValidationInfo) -> Path:
    """A path of a config, against the folder of the config file (the validation context's
    ``folder``, a `ConfigFolder`, which `load` passes); ValueError where it may not reach."""
    folder = (info.context or {}).get("folder")
    return folder.path(path) if folder is not None else path
