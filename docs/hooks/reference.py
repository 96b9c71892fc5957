"""MkDocs hook: the pages generated from the code when the manual is built.

A page asks for generated text by a marker comment on a line of its own:

``<!-- config-fields: MODULE:MODEL -->``
    the table of every field of a pydantic config model (dotted path, type, default, unit,
    meaning), from the model's JSON schema, so that the reference cannot drift from what the
    config files accept;
``<!-- notebook: PATH -->``
    a jupytext "percent" script (relative to ``docs/``) as a page: its markdown cells as text,
    its code cells as Python blocks.

The command reference is mkdocs-click's (``docs/reference/cli.md``), the Python reference
mkdocstrings' (``docs/reference/api.md``).
"""

from __future__ import annotations

import importlib
import json
import re
from pathlib import Path
from typing import Any

MARKER = re.compile(r"^<!-- (config-fields|notebook): (\S+) -->$", re.M)
UNIT = re.compile(r"\s*\[([^\[\]]+)\]\s*$")
"""A description's trailing unit in brackets, as the config models write it: ``... [m]``."""

INSIDE = re.compile(r"(?<!\S)\[([^\[\]\s]{1,12})\]")
"""A unit in brackets inside a description: after a space, short, without spaces (``[s]``,
``[g]``, ``[Hz]``; not the extra of ``pip install 'rockbridge[fema]'``)."""

DOCS = Path(__file__).resolve().parents[1]


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    """Replace each marker of a page by its generated text (MkDocs' event)."""
    return MARKER.sub(lambda m: GENERATORS[m.group(1)](m.group(2)), markdown)


def config_fields(target: str) -> str:
    """The markdown table of every field of the model ``MODULE:MODEL``."""
    module, _, name = target.partition(":")
    schema = getattr(importlib.import_module(module), name).model_json_schema()
    rows = ["| field | type | default | unit | meaning |", "|---|---|---|---|---|"]
    for path, field, required in fields(schema, schema, "", ()):
        description = " ".join(field.get("description", "").split())
        unit, meaning = unit_of(description, numeric(field))
        cells = (type_of(schema, field), default_of(field, required), unit, meaning)
        rows.append(f"| `{path}` | " + " | ".join(escape(cell) for cell in cells) + " |")
    return "\n".join(rows)


def unit_of(description: str, numeric: bool) -> tuple[str, str]:
    """(unit, meaning) of a field's description: its trailing ``[unit]`` taken off, else, for a
    field that holds numbers, the first short bracket inside it (``T_p [s]; or give
    frequency``), which stays in the text."""
    trailing = UNIT.search(description)
    if trailing:
        return trailing.group(1), UNIT.sub("", description)
    inside = INSIDE.search(description) if numeric else None
    return (inside.group(1) if inside else ""), description


def numeric(field: dict) -> bool:
    """Whether a field's value is or holds numbers (not through another model)."""
    return re.search(r'"type": "(number|integer)"', json.dumps(field)) is not None


def fields(root: dict, model: dict, prefix: str, seen: tuple[str, ...]):
    """(dotted path, field schema, required) of each field of ``model``, depth first: a field
    whose value is a model (alone, in a list, as a mapping's values or among the forms it may
    take) is followed by that model's fields; forms that share a place (the kinds of a
    discriminated union) each under their name, `form_name`."""
    required = set(model.get("required", ()))
    for name, wrapped in model.get("properties", {}).items():
        field = unwrapped(wrapped)
        path = f"{prefix}{name}"
        yield path, field, name in required
        forms = nested(field)
        for suffix, form in forms:
            ref = form.get("$ref", "")
            if ref in seen:
                continue
            target = root["$defs"][ref_name(form)] if ref else form
            shared = [s for s, _ in forms].count(suffix) > 1
            label = f".<{form_name(target)}>" if shared else ""
            yield from fields(root, target, f"{path}{suffix}{label}.", (*seen, ref))


def unwrapped(field: dict) -> dict:
    """A field's schema with a lone ``allOf`` merged into it: pydantic before 2.9 wraps a model
    field's ``$ref`` so, beside its default and description (later versions do not)."""
    if len(field.get("allOf", ())) != 1:
        return field
    return {**{k: v for k, v in field.items() if k != "allOf"}, **field["allOf"][0]}


def nested(field: dict) -> list[tuple[str, dict]]:
    """(path suffix, schema) of each model a field's value may be, a ``$ref`` or an inline
    object with properties, through any depth of alternatives, lists and mappings: the suffix
    ``""`` for the field itself, ``[]`` for a list's entries, ``.<key>`` for a mapping's values
    (so ``[]`` for each kind of a list of devices, ``.<key>[]`` for a mapping to lists)."""
    field = unwrapped(field)
    if "$ref" in field or "properties" in field:
        return [("", field)]
    options = field.get("anyOf", field.get("oneOf", ()))
    found = [form for option in options for form in nested(option)]
    if isinstance(field.get("items"), dict):
        found += [("[]" + suffix, form) for suffix, form in nested(field["items"])]
    if isinstance(field.get("additionalProperties"), dict):
        found += [(".<key>" + s, form) for s, form in nested(field["additionalProperties"])]
    return found


def form_name(model: dict) -> str:
    """The name of one of a field's forms: the value of the key that tells it from the others
    (a required key of one constant value: ``tendon`` of ``kind: tendon``), else its title."""
    for key in model.get("required", ()):
        values = [model["properties"][key].get("const")] + model["properties"][key].get("enum", [])
        values = [value for value in values if value is not None]
        if len(set(values)) == 1:
            return str(values[0])
    return str(model.get("title", "mapping"))


def ref_name(option: dict) -> str:
    """The model a ``$ref`` names (``#/$defs/Name`` → ``Name``)."""
    return option["$ref"].rsplit("/", 1)[1]


def type_of(root: dict, field: dict) -> str:
    """A short type: ``number``, ``list of string``, ``[number, number]``, ``one of a, b``, a
    model's name, …"""
    field = unwrapped(field)
    if "$ref" in field:
        return ref_name(field)
    if "const" in field:
        return json.dumps(field["const"])
    if "enum" in field:
        return "one of " + ", ".join(str(value) for value in field["enum"])
    options = field.get("anyOf", field.get("oneOf"))
    if options:
        kinds = [type_of(root, o) for o in options if o.get("type") != "null"]
        return " or ".join(dict.fromkeys(kinds))
    if "prefixItems" in field:  # a tuple: (low, high)
        return "[" + ", ".join(type_of(root, item) for item in field["prefixItems"]) + "]"
    if field.get("type") == "array":
        return "list of " + type_of(root, field.get("items", {}))
    if "properties" in field:
        return "mapping"
    if field.get("type") == "object" and isinstance(field.get("additionalProperties"), dict):
        return "mapping to " + type_of(root, field["additionalProperties"])
    return str(field.get("type", "any"))


def default_of(field: dict, required: bool) -> str:
    """``required``, the default as YAML would write it (a large number with its exponent:
    ``1.95e+11``), or ``–`` (none: the field is left out)."""
    if required:
        return "required"
    if "default" not in field or field["default"] is None:
        return "–"
    default = field["default"]
    if isinstance(default, float) and abs(default) >= 1e6:
        return f"{default:.6g}"
    return json.dumps(default, ensure_ascii=False)


def escape(cell: str) -> str:
    """A table cell of text: no pipe breaks the row, no ``<stem>`` is taken for an HTML tag."""
    return cell.replace("|", "\\|").replace("<", "&lt;")


def notebook(target: str) -> str:
    """A jupytext percent script as markdown: ``# %% [markdown]`` cells as text (their ``# ``
    stripped, their headings a level down, under the page's title), ``# %%`` cells as Python
    blocks, the jupytext header left out."""
    text = (DOCS / target).read_text(encoding="utf-8")
    parts = []
    for cell in re.split(r"^# %%", text, flags=re.M)[1:]:
        head, _, body = cell.partition("\n")
        if head.strip() == "[markdown]":
            lines = [re.sub(r"^# ?", "", line) for line in body.strip("\n").splitlines()]
            parts.append("\n".join(re.sub(r"^(#+ )", r"#\1", line) for line in lines))
        elif body.strip():
            parts.append("```python\n" + body.strip("\n") + "\n```")
    return "\n\n".join(parts)


GENERATORS = {"config-fields": config_fields, "notebook": notebook}
