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
