"""The options table of docs/python_api.md, made from the option table (shadecut.option_fields()).

    PYTHONPATH=addon /usr/bin/python3 scripts/option_docs.py           # rewrites the table in the docs
    PYTHONPATH=addon /usr/bin/python3 scripts/option_docs.py --check   # exit 1 when the docs differ

The table's rows are the option table's (native/src/pipeline/option_table.cpp), in its order; the
docs hold nothing of an option that the table does not say.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import shadecut

DOCS = Path(__file__).resolve().parents[1] / "docs" / "python_api.md"
BEGIN = "<!-- the options: made from the option table by scripts/option_docs.py, not edited by hand -->"
END = "<!-- end of the options -->"


def shown_default(field: dict) -> str:
    """The default as Python shows it: 36, 0.2, True, None, `graphcut`."""
    value = field["default"]
    if hasattr(value, "name") and hasattr(value, "value"):
        return f"`{value.name}`"
    return repr(value)


def allowed(field: dict) -> str:
    if field["choices"]:
        return ", ".join(f"`{choice}`" for choice in field["choices"]) + (" or None" if field["default"] is None else "")
    if field["kind"] == "flag":
        return "True, False"
    words = field["range"]
    return words + (" or None" if field["default"] is None else "")


def table() -> str:
    lines = [BEGIN, "| option | stage | default | allowed | meaning |", "|---|---|---|---|---|"]
    for field in shadecut.option_fields():
        help_text = field["help"].replace("|", "\\|")
        lines.append(f"| `{field['name']}` | {field['group']} | {shown_default(field)} | {allowed(field)} | {help_text} |")
    return "\n".join(lines + [END])


def with_table(text: str) -> str:
    """The docs' text with its options table made again."""
    start, end = text.index(BEGIN), text.index(END) + len(END)
    return text[:start] + table() + text[end:]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", action="store_true", help="only say whether the docs hold the table as made now")
    arguments = parser.parse_args()
    text = DOCS.read_text()
    made = with_table(text)
    if arguments.check:
        if made != text:
            print(f"{DOCS}: the options table differs from the option table; run scripts/option_docs.py", file=sys.stderr)
            return 1
        return 0
    DOCS.write_text(made)
    return 0


if __name__ == "__main__":
    sys.exit(main())
