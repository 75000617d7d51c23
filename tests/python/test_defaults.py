"""Defaults are held once, in C++ (ReconstructOptions): every layer reads them from there."""

import inspect
import re
import subprocess
from pathlib import Path

import shadecut

CLI = Path(__file__).resolve().parents[2] / "build" / "native" / "shadecut"
DEFAULTS = shadecut.ReconstructOptions()


def cli_default(help_text: str, flag: str) -> str:
    """The '(default X)' stated in the CLI's help for one flag (its entry may span lines)."""
    entry = re.search(rf"^  {re.escape(flag)} .*?\(default ([^)]+)\)", help_text, re.M | re.S)
    assert entry, f"{flag} states no default in --help"
    return entry.group(1)


def test_the_cli_help_states_the_bound_defaults():
    help_text = subprocess.run([str(CLI), "--help"], capture_output=True, text=True, check=True).stdout
    assert cli_default(help_text, "--method") == DEFAULTS.method.name
    assert cli_default(help_text, "--scene") == DEFAULTS.scene.name
    relief = DEFAULTS.replace(scene="relief")
    assert cli_default(help_text, "--light-method").split() == [
        DEFAULTS.light_method_used().name, "for", "an", "object,", relief.light_method_used().name, "for", "a", "relief"]
    assert cli_default(help_text, "--integrator") == DEFAULTS.integrator.name
    assert int(cli_default(help_text, "--labels")) == DEFAULTS.labels
    assert float(cli_default(help_text, "--data-weight")) == DEFAULTS.data_weight
    assert int(cli_default(help_text, "--band")) == DEFAULTS.coarse_to_fine_band
    assert int(cli_default(help_text, "--band-radius")) == DEFAULTS.coarse_to_fine_radius
    assert int(cli_default(help_text, "--threads")) == DEFAULTS.threads
    assert cli_default(help_text, "--fit-shading") == ("on" if DEFAULTS.fit_shading else "off")
    assert float(cli_default(help_text, "--fit-smoothness")) == DEFAULTS.fit_smoothness
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


def test_the_docs_state_every_bound_option_default():
    rows = table_rows("option")
    assert set(rows) == set(shadecut.OPTION_NAMES)
    for name, cells in rows.items():
        default = cells[0]
        value = getattr(DEFAULTS, name)
        if default == "per method":
            assert value is None, name
            continue
        expected = value.name if hasattr(value, "name") and hasattr(value, "value") else value
        if isinstance(expected, bool) or expected is None or isinstance(expected, str):
            assert documented(default) == expected, name
        else:
            assert documented(default) == float(expected), name


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
    assert "never with one albedo" in row
    assert f"{retinex.highlight_threshold_used():g} with `retinex`" in row
    assert retinex.replace(highlight_threshold=0.0).highlight_threshold_used() == 0.0
