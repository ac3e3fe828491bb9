"""``spectrace help``: every plugin's reference page, alone and in one format.

The format (issue 14 item 3): a title line naming the XML type, the sections Parameters
(a table with the columns parameter, type, default, unit, description), Formula, Sources
(author and year) and Example (XML that loads), marks |exposed| |differentiable|
|discontinuous| explained; no reference to material users do not have.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from spectrace.cli import main
from spectrace.commands import help as help_command

README = Path(__file__).resolve().parents[2] / "README.md"
PAGES = help_command.pages()
PLUGIN_PAGES = [name for name, module in PAGES.items() if help_command.kind(module) != "helper"]
SECTIONS = ("Parameters", "Formula", "Sources", "Example")
TABLE_HEADER = re.compile(r"^parameter\s+type\s+default\s+unit\s+description$", re.M)
#: Words of pages written for a course or a design file, which users do not have.
FOREIGN = ("the lecture", "DESIGN.md", "design file")


def test_help_prints_the_page_alone(capsys):
    """``spectrace help phong`` prints phong's page: its title, its table and its example,
    and none of the methods of Python's help()."""
    assert main(["help", "phong"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("``phong``")
    assert TABLE_HEADER.search(out)
    assert '<bsdf type="phong">' in out
    assert "Methods inherited" not in out and "__init__" not in out


def test_help_lists_the_plugins_and_the_shared_pages(capsys):
    """Without a name: one line per plugin, then the helper pages the plugins' pages refer to
    (falloff, luminous, fog, params); the base modules lobes and delta are no plugins and are
    not listed, though their pages print."""
    assert main(["help"]) == 0
    out = capsys.readouterr().out
    for name in PLUGIN_PAGES:
        assert re.search(rf"^  {name} ", out, re.M), name
    shared = out.split("share: ", 1)[1].split(";", 1)[0].split(", ")
    assert {"falloff", "luminous", "fog", "params"} <= set(shared)
    for name in help_command.UNLISTED:
        assert name not in out
        assert main(["help", name]) == 0 and capsys.readouterr().out


def test_unknown_page_is_one_line(capsys):
    """An unknown name: exit 2 and one error line listing the pages."""
    assert main(["help", "phongg"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "phongg" in err and "pointlight" in err


def test_help_imports_no_mitsuba():
    """Pages are read from the sources: printing one imports neither mitsuba nor a plugin."""
    code = ("import sys; from spectrace.cli import main; main(['help', 'local']); "
            "assert 'mitsuba' not in sys.modules and 'drjit' not in sys.modules, 'imported'")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    assert "``local``" in done.stdout


@pytest.mark.parametrize("name", PLUGIN_PAGES)
def test_plugin_pages_share_one_format(name):
    """Every plugin page has the four sections, the five-column table, a mark legend when
    marks are used, sources with years, and no reference to course material."""
    page = help_command.page(name)
    assert page.startswith(f"``{name}``")
    for section in SECTIONS:
        assert re.search(rf"^{section}\n-+$", page, re.M), section
    assert TABLE_HEADER.search(page)
    assert "list-table" not in page
    sources = page.split("\nSources\n", 1)[1].split("\nExample\n", 1)[0]
    assert re.search(r"\((19|20)\d\d\)", sources)
    for word in FOREIGN:
        assert word not in page, word
    if "|differentiable|" in page:
        assert "\nMarks\n" in page


@pytest.mark.parametrize("name", [n for n in PLUGIN_PAGES if n != "ieslight"])
def test_plugin_page_example_loads(variant_spectral, name):
    """The XML example of every plugin page loads in Mitsuba as written (ieslight's needs
    its luminaire file and is loaded by its own tests)."""
    import mitsuba as mi

    example = help_command.page(name).split("\nExample\n", 1)[1]
    xml = re.search(rf"^    (<(\w+) type=\"{name}\".*?^    </\2>)", example, re.M | re.S)
    assert xml, "no XML example"
    text = re.sub(r"^    ", "", xml.group(1), flags=re.M)
    mi.load_string(text.replace(f'type="{name}"', f'type="{name}" version="3.0.0"', 1))


def test_readme_help_commands_work(capsys):
    """Every ``spectrace help ...`` command the README shows runs and prints a page."""
    commands = re.findall(r"`spectrace (help(?: [a-z_]+)?)`", README.read_text())
    assert commands, "the README shows no spectrace help command"
    for command in commands:
        assert main(command.split()) == 0, command
        assert capsys.readouterr().out.strip(), command


def test_page_names_are_forgiving(capsys):
    """``help PHONG`` is the page of phong; a misspelt name is answered with the closest
    page and a pointer to Mitsuba's own plugins, in one line."""
    assert main(["help", "PHONG"]) == 0
    assert capsys.readouterr().out.startswith("``phong``")
    assert main(["help", "pointlite"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "did you mean 'pointlight'" in err and "Mitsuba" in err


def test_reader_that_stops_early_is_no_traceback():
    """``spectrace help ieslight | head -1``: the reader closes the pipe, the command ends
    quietly (it printed a BrokenPipeError traceback)."""
    import os

    read, write = os.pipe()
    os.close(read)  # the reader is gone before the page is written
    code = "from spectrace.cli import main; raise SystemExit(main(['help', 'ieslight']))"
    done = subprocess.run([sys.executable, "-c", code], stdout=write, stderr=subprocess.PIPE,
                          text=True, timeout=60)
    os.close(write)
    assert done.returncode == 0 and "BrokenPipe" not in done.stderr, done.stderr


def test_any_command_whose_reader_stops_early_is_no_traceback():
    """``spectrace render --help | head -1``: a closed pipe ends any command quietly (the
    command line's own handler, not each command's)."""
    import os

    read, write = os.pipe()
    os.close(read)
    code = "from spectrace.cli import main; raise SystemExit(main(['render', '--help']))"
    done = subprocess.run([sys.executable, "-c", code], stdout=write, stderr=subprocess.PIPE,
                          text=True, timeout=60)
    os.close(write)
    assert done.returncode == 0 and "BrokenPipe" not in done.stderr, done.stderr
