"""One name per meaning across the commands (the old --step spellings still work, with a deprecation
message), and each front door naming an engine refusal's remedy in its own terms: a flag that
`ruled fit --help` lists on the command line, a keyword of the call in Python (FreeCAD's properties are
checked in tests/workbench/test_workbench_features.py)."""
import re

import pytest
from conftest import ruled_here

from ruled import FitOptions, fit_surface
from ruled.cli.parser import build_parser
from ruled.core.errors import BadInputError, TooBigError
from ruled.examples import elber_ex1


@pytest.mark.parametrize("argv, new, value", [
    (["fit", "in.step", "--face", "0", "--step", "0.5", "-o", "o.step"], "--lift-step", 0.5),
    (["split", "in.step", "--face", "0", "--step", "0.25", "-o", "o.step"], "--lift-step", 0.25),
    (["cone", "in.step", "--face", "0", "--tol", "1", "--step", "0.2", "-o", "o.step"], "--arc-step", 0.2),
    (["machine", "in.step", "--face", "0", "--xyuv", "--step", "cam.step", "-o", "o.ngc"], "--cam-step", "cam.step"),
])
def test_old_step_spellings_still_work_with_a_deprecation_message(argv, new, value, capsys):
    args = build_parser().parse_args(argv)
    assert args.step == value
    err = capsys.readouterr().err
    assert f"--step of 'ruled {argv[0]}' is now {new}" in err and "next release" in err
    renamed = build_parser().parse_args([new if a == "--step" else a for a in argv])
    assert renamed.step == value and capsys.readouterr().err == ""


@pytest.mark.parametrize("command, new", [("fit", "--lift-step"), ("split", "--lift-step"), ("cone", "--arc-step"),
                                          ("machine", "--cam-step")])
def test_help_shows_the_new_spelling_only(command, new):
    out = " ".join(ruled_here(command, "--help").stdout.split())
    assert new in out and "formerly --step" in out
    assert not re.search(r"(?<![\w-])--step\b(?! )", out.replace("formerly --step", ""))


def _flags(text: str) -> set:
    return set(re.findall(r"(?<![\w-])--[a-z][a-z-]*", text))


def test_a_refusal_names_its_remedy_in_python_and_on_the_command_line(tmp_path):
    """The same refusal (a DP table too big for the memory allowed) through two front doors: in Python a
    keyword of FitOptions and the error's fields; on the command line a flag that `ruled fit --help` lists."""
    with pytest.raises(TooBigError) as info:
        fit_surface(elber_ex1(), FitOptions(samples=3000, memory_cap=2.0 ** 20))
    exc = info.value
    assert exc.option == "samples" and exc.options == ("samples",)
    assert "--" not in str(exc) and "samples=3000" in exc.problem
    m = re.search(r"use samples=(\d+) or fewer", exc.remedy)
    assert m and 3 <= int(m.group(1)) < 3000
    assert "samples" in FitOptions.__dataclass_fields__

    from ruled.examples import elber_ex2
    from ruled.occ.convert import container_to_face
    from ruled.occ.io import write_step
    src = str(tmp_path / "ex2.step")
    write_step(container_to_face(elber_ex2()), src)
    run = ruled_here("fit", src, "--face", "0", "--samples", "3000", "--memory-cap", "1", "-o",
                     str(tmp_path / "o.step"))
    assert run.returncode == 2, run.stderr
    line = run.stderr.strip()
    assert line.startswith("ruled: error: --samples 3000 needs about") and "«" not in line
    assert re.search(r"use --samples \d+ or fewer$", line)
    assert _flags(line) <= _flags(ruled_here("fit", "--help").stdout), line


@pytest.mark.parametrize("options, key, python, cli", [
    (dict(samples=2), "samples", "samples=2", "--samples 2"),
    (dict(max_error=-1.0), "max_error", "max_error must be", "--max-error must be"),
    (dict(method="4d", step=0.0), "lift_step", "step must be", "--lift-step must be"),
    (dict(method="4d", elevations=500), "elevations", "elevations=500", "--elevations 500"),
])
def test_bad_fit_options_name_the_option_in_each_doors_terms(options, key, python, cli):
    from ruled.cli.common import cli_text
    with pytest.raises(BadInputError) as info:
        FitOptions(**options).checked()
    exc = info.value
    assert exc.option == key
    assert str(exc).startswith(python) and "--" not in str(exc)
    assert cli_text(exc).startswith(cli)
    assert _flags(cli_text(exc)) <= _flags(ruled_here("fit", "--help").stdout)
