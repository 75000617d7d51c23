"""Defaults are held once, in C++ (ReconstructOptions): every layer reads them from there."""

import inspect
import re
import subprocess
import sys
from pathlib import Path

import shadecut

CLI = Path(__file__).resolve().parents[2] / "build" / "native" / "shadecut"
DEFAULTS = shadecut.ReconstructOptions()


def cli_default(help_text: str, flag: str) -> str:
    """The '[default X' stated in the CLI's help for one flag (its entry may span lines)."""
    entry = re.search(rf"^  {re.escape(flag)}\b.*?\[default ([^;\]]+)", help_text, re.M | re.S)
    assert entry, f"{flag} states no default in --help"
    return entry.group(1)


def test_the_cli_help_states_the_bound_defaults():
    help_text = subprocess.run([str(CLI), "--help"], capture_output=True, text=True, check=True).stdout
    for field in shadecut.option_fields():
        flag = "--" + field["name"].replace("_", "-")
        assert cli_default(help_text, flag) == field["default_text"], flag
    assert cli_default(help_text, "--method") == DEFAULTS.method.name
    assert int(cli_default(help_text, "--labels")) == DEFAULTS.labels
    # light_method's help names the estimators used when it is None, as light_method_used() picks them.
    relief = DEFAULTS.replace(scene="relief")
    assert (f"{DEFAULTS.light_method_used().name} for an object, {relief.light_method_used().name} for a relief"
            in " ".join(help_text.split()))
    assert "--maxflow" not in help_text  # the test solvers are no user option


def test_python_has_no_defaults_of_its_own():
    # reconstruct takes the options as keywords and fills the rest from ReconstructOptions.
    parameters = inspect.signature(shadecut.reconstruct).parameters
    assert not set(parameters) & set(shadecut.OPTION_NAMES)
    # estimate_light's default estimator is reconstruct's.
    assert inspect.signature(shadecut.estimate_light).parameters["method"].default is None


def test_options_round_trip_every_field_and_take_enum_names():
    options = shadecut.ReconstructOptions(method="lee_rosenfeld", integrator=shadecut.Integrator.frankot_chellappa,
                                          light_method="lee_rosenfeld", labels=12, tolerance=0.01)
    assert options.method == shadecut.Method.lee_rosenfeld
    assert options.integrator == shadecut.Integrator.frankot_chellappa
    assert options.light_method == shadecut.LightMethod.lee_rosenfeld
    assert (options.labels, options.tolerance) == (12, 0.01)
    assert options.replace(labels=8).labels == 8 and options.labels == 12  # replace copies
    assert set(shadecut.OPTION_NAMES) == set(re.findall(r"(\w+)=", repr(DEFAULTS)))
    assert tuple(shadecut.Method.__members__) == shadecut.METHODS
    assert tuple(shadecut.LightMethod.__members__) == shadecut.LIGHT_METHODS


DOCS = Path(__file__).resolve().parents[2] / "docs" / "python_api.md"


def table_rows(first_header: str) -> dict:
    """The rows of the docs table whose first header cell is ``first_header``: {first cell: cells}."""
    lines = DOCS.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(f"| {first_header} |"))
    rows = {}
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [cell.strip() for cell in line.strip("|").split("|")]
        rows[cells[0].strip("`")] = cells[1:]
    return rows


def documented(cell: str):
    """A documented default as a value: numbers, True/False, None, an enum name, or '—' for unused."""
    literal = cell.split(" (")[0].strip("`")
    if literal == "—":
        return 0
    if literal in ("True", "False", "None"):
        return {"True": True, "False": False, "None": None}[literal]
    try:
        return float(literal)
    except ValueError:
        return literal


def test_the_docs_options_table_is_made_from_the_option_table():
    """docs/python_api.md's options are the option table's rows, in its order, as scripts/option_docs.py makes them."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
    import option_docs

    text = DOCS.read_text()
    assert option_docs.with_table(text) == text, "run scripts/option_docs.py"
    rows = table_rows("option")
    assert list(rows) == list(shadecut.OPTION_NAMES) == [field["name"] for field in shadecut.option_fields()]
    for name, cells in rows.items():
        value = getattr(DEFAULTS, name)
        expected = value.name if hasattr(value, "name") and hasattr(value, "value") else value
        if isinstance(expected, (bool, str)) or expected is None:
            assert documented(cells[1]) == expected, name
        else:
            assert documented(cells[1]) == float(expected), name


def test_every_layer_has_every_field_of_the_table():
    """A new row of the option table is a Python property, a keyword of reconstruct(), a flag with its
    default in --help and a row of the docs' table: each is made by iterating the table."""
    help_text = subprocess.run([str(CLI), "--help"], capture_output=True, text=True, check=True).stdout
    names = [field["name"] for field in shadecut.option_fields()]
    assert names == list(shadecut.OPTION_NAMES)
    assert set(names) == set(re.findall(r"(\w+)=", repr(DEFAULTS)))
    for name in names:
        assert hasattr(DEFAULTS, name)
        assert f"\n  --{name.replace('_', '-')}" in help_text
        assert f"| `{name}` |" in DOCS.read_text()


def test_the_docs_state_every_method_default():
    rows = table_rows("method")
    assert set(rows) == set(shadecut.METHODS)
    fields = ("min_curvature", "undefined_weight", "tolerance", "iterations", "smoothness")
    for method, cells in rows.items():
        values = shadecut.method_defaults(method)
        assert [documented(cell) for cell in cells] == [float(getattr(values, f)) for f in fields], method
        # A field the method uses for an option left None is shown beside it.
        shown = repr(shadecut.ReconstructOptions(method=method))
        assert f"min_curvature=None ({method}: {values.min_curvature!r})" in shown


def test_the_highlight_threshold_left_none_follows_the_albedo_method_as_the_docs_say():
    row = " ".join(table_rows("option")["highlight_threshold"])
    retinex = DEFAULTS.replace(albedo_method="retinex")
    assert DEFAULTS.highlight_threshold is None and DEFAULTS.highlight_threshold_used() <= 0.0
    assert "never otherwise" in row
    assert f"{retinex.highlight_threshold_used():g} with retinex" in row
    assert retinex.replace(highlight_threshold=0.0).highlight_threshold_used() == 0.0
