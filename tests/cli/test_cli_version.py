"""``beveloid --version`` prints the installed version (looked up only when asked)."""
from importlib.metadata import version

from beveloid import cli


def test_version_is_the_installed_one(capsys):
    assert cli.main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"beveloid {version('beveloid')}"


def test_help_lists_the_version_flag(capsys):
    assert cli.main(["--help"]) == 0
    assert "--version" in capsys.readouterr().out
