"""The command line's reference page (reference/cli), generated from `wgputrace.cli.argument_parser`
when the site builds: each command's usage, description and a table of its arguments (choices,
default, help), so the page says what the parser accepts and nothing else."""

from __future__ import annotations

import argparse
import functools
from pathlib import Path

from sphinx.application import Sphinx

from wgputrace.cli import argument_parser

from .generated_files import markdown_table, write_page

PAGE = "reference/cli.md"
# usage lines wrapped at a fixed width, not the width of the terminal that builds the site
USAGE_WIDTH = 80


def _default(action: argparse.Action) -> str:
    default = action.default
    if default in (None, argparse.SUPPRESS) or isinstance(action, argparse._StoreTrueAction):
        return ""
    if isinstance(default, Path) and default == Path.cwd():
        return "the current folder"
    if isinstance(default, tuple) and len(default) == 2 and all(isinstance(v, int) for v in default):
        return f"`{default[0]}x{default[1]}`"
    return f"`{default}`"


def _values(action: argparse.Action) -> str:
    if action.choices is not None and not isinstance(action, argparse._SubParsersAction):
        return " \\| ".join(f"`{choice}`" for choice in action.choices)
    if action.nargs == 0:
        return "a flag"
    return f"`{action.metavar or action.dest.upper()}`"


def _arguments(parser: argparse.ArgumentParser) -> str:
    rows = []
    for action in parser._actions:
        if isinstance(action, (argparse._HelpAction, argparse._SubParsersAction)):
            continue
        names = ", ".join(f"`{name}`" for name in action.option_strings) or f"`{action.dest}` (positional)"
        help_text = (action.help or "") % {"default": action.default, "prog": parser.prog}
        rows.append((names, _values(action), _default(action), help_text))
    return markdown_table(("argument", "takes", "default", "what it does"), rows)


def _usage(parser: argparse.ArgumentParser) -> str:
    parser.formatter_class = functools.partial(argparse.HelpFormatter, width=USAGE_WIDTH)
    return parser.format_usage().strip()


def _commands(parser: argparse.ArgumentParser) -> list[tuple[str, str, argparse.ArgumentParser]]:
    """(name, help, parser) of each subcommand, in the order the parser lists them."""
    found = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {choice.dest: choice.help for choice in action._choices_actions}
            found += [(name, helps.get(name, ""), sub) for name, sub in action.choices.items()]
    return found


def page() -> str:
    parser = argument_parser()
    sections = [
        f"# Command line\n\n{parser.description}\n\n```text\n{_usage(parser)}\n```\n\n"
        f"{parser.epilog or ''}\n\n{_arguments(parser)}\n"
        "The same program runs as `python -m wgputrace`; `python app.py` takes the arguments of `view`. "
        "This page is generated from `wgputrace.cli.argument_parser` when the site is built.\n"
    ]
    for name, help_text, sub in _commands(parser):
        description = f"{sub.description}\n\n" if sub.description else ""
        sections.append(
            f"## {name}\n\n{help_text[0].upper()}{help_text[1:]}.\n\n```text\n{_usage(sub)}\n```\n\n"
            f"{description}{_arguments(sub)}"
        )
    return "\n".join(sections)


def generate(app: Sphinx) -> None:
    write_page(Path(app.srcdir) / PAGE, page())


def setup(app: Sphinx) -> dict[str, object]:
    app.connect("builder-inited", generate)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
