"""MkDocs hook: a line `<!-- api: dotted.name -->` in a page becomes that function's or class's signature and
docstring, read from the code at build time (so the reference cannot drift from it)."""
import importlib
import inspect
import re

_API = re.compile(r"^<!-- api: ([\w.]+) -->$", re.M)


def _entry(dotted: str) -> str:
    module, _, name = dotted.rpartition(".")
    obj = getattr(importlib.import_module(module), name)
    try:
        sig = str(inspect.signature(obj))
    except (TypeError, ValueError):
        sig = "(...)"
    kind = "class" if inspect.isclass(obj) else "def"
    doc = inspect.getdoc(obj) or ""
    return f"### `{dotted}`\n\n```python\n{kind} {name}{sig}\n```\n\n{doc}\n"


def on_page_markdown(markdown, page, config, files, **kw):
    return _API.sub(lambda m: _entry(m.group(1)), markdown)
