"""The command-line reference of the site, generated from the program's own parser.

``command_line_markdown()`` renders :func:`validation.cli.build_parser` as Markdown: the
program's usage, then one section per command (its one-line help, its usage, and a table of
every argument and option with the parser's help text). docs/conf.py puts it in place of the
line :data:`MARKER` of ``guide/command-line.md`` at every build, so the page lists exactly the
commands and options that ``python -m validation COMMAND --help`` prints and cannot drift from
them. ``python docs/cli_pages.py`` prints it.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]

#: The line of guide/command-line.md that the generated reference replaces.
MARKER = "<!-- generated: every command and option of python -m validation -->"
#: Width of the usage lines (argparse wraps to the terminal; the page must not depend on it).
WIDTH = 96


def _subcommands(parser: argparse.ArgumentParser):
    """(name, one-line help, parser) of every command, in the parser's order."""
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    helps = {choice.dest: choice.help for choice in action._choices_actions}
    return [(name, helps.get(name, ""), sub) for name, sub in action.choices.items()]


def _formatter(parser: argparse.ArgumentParser) -> argparse.HelpFormatter:
    return parser.formatter_class(prog=parser.prog, width=WIDTH)


def _cell(text: str) -> str:
    """Text for a Markdown table cell: one line, pipes escaped, the user's home as ``~``."""
    text = " ".join(str(text).split()).replace("|", "\\|")
    home = os.path.expanduser("~")
    return text.replace(home, "~") if home not in ("", "/") else text


def _usage(parser: argparse.ArgumentParser) -> str:
    formatter = _formatter(parser)
    formatter.add_usage(parser.usage, parser._actions, parser._mutually_exclusive_groups,
                        prefix="")
    return formatter.format_help().strip()


def _arguments(parser: argparse.ArgumentParser) -> list[str]:
    """Table rows (Markdown) of every argument of ``parser`` but ``--help``."""
    formatter = _formatter(parser)
    exclusive = {id(action): group for group in parser._mutually_exclusive_groups
                 for action in group._group_actions}
    rows = []
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction):
            continue
        invocation = formatter._format_action_invocation(action)
        text = formatter._expand_help(action) if action.help else ""
        group = exclusive.get(id(action))
        if group is not None:
            others = [o for a in group._group_actions if a is not action
                      for o in a.option_strings[:1]]
            text += f" (not with {', '.join(others)})"
        kind = "option" if action.option_strings else "argument"
        rows.append(f"| `{_cell(invocation)}` | {kind} | {_cell(text)} |")
    return rows


def command_line_markdown(parser: argparse.ArgumentParser | None = None, *,
                          level: int = 2) -> str:
    """The reference of every command and option of ``parser`` (default: the program's own),
    as Markdown with headings of ``level``."""
    if parser is None:
        from validation.cli import build_parser

        parser = build_parser()
    heading = "#" * level
    commands = _subcommands(parser)
    lines = ["```text", _usage(parser), "```", "", "| command | what it does |", "|---|---|"]
    lines += [f"| [`{name}`](#{_anchor(sub)}) | {_cell(text)} |" for name, text, sub in commands]
    lines.append("")
    for _, text, sub in commands:
        sentence = _cell(text)
        lines += [f"{heading} `{sub.prog}`", "", f"{sentence[:1].upper()}{sentence[1:]}.", "",
                  "```text", _usage(sub), "```", ""]
        rows = _arguments(sub)
        if rows:
            lines += ["| argument | kind | what it does |", "|---|---|---|"] + rows + [""]
        else:
            lines += ["No arguments.", ""]
    return "\n".join(lines)


def _anchor(parser: argparse.ArgumentParser) -> str:
    """The anchor MyST gives the heading of ``parser``'s section (its ``prog`` in backticks)."""
    words = "".join(c if c.isalnum() or c in " -_" else "" for c in parser.prog.lower())
    return "-".join(words.split())


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    print(command_line_markdown())
