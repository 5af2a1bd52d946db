"""The command line's parser in the command's language.

The help texts of the options are translated where the parser is built; argparse's own
words (``usage:``, ``options:``, ``positional arguments``, the help option's line, ``error:``
and its common refusals) come from the lab's catalog here, not from gettext's global domain,
which the lab never sets.
"""

from __future__ import annotations

import argparse
import functools
import re
import sys
from collections.abc import Iterable, Sequence
from typing import Any, NoReturn

from analyzer_lab.i18n import ENGLISH, N_, Language

EXIT_USAGE = 2

#: argparse's refusals the lab says in its language (argparse writes them in English); a
#: refusal not listed is shown as argparse writes it.
REFUSALS = (
    N_("the following arguments are required: %s"),
    N_("unrecognized arguments: %s"),
    N_("argument %(argument_name)s: %(message)s"),
    N_("invalid choice: %(value)r (choose from %(choices)s)"),
    N_("invalid %(type)s value: %(value)r"),
    N_("expected one argument"),
    N_("expected at least one argument"),
    N_("ambiguous option: %(option)s could match %(matches)s"),
    N_("not allowed with argument %s"),
    N_("ignored explicit argument %r"),
)
_SPEC = re.compile(r"%(?:\((\w+)\))?[sr]")


def _pattern(template: str) -> re.Pattern[str]:
    """``template`` as a regular expression, one named group per placeholder."""
    out, pos = [], 0
    for m in _SPEC.finditer(template):
        out += [re.escape(template[pos : m.start()]), f"(?P<{m.group(1) or 's'}>.+?)"]
        pos = m.end()
    out.append(re.escape(template[pos:]))
    return re.compile("".join(out), re.S)


_PATTERNS = tuple((t, _pattern(t)) for t in REFUSALS)


def refusal(message: str, language: Language) -> str:
    """argparse's refusal ``message`` in ``language`` (as it is when not one of
    :data:`REFUSALS`); the argument's names and values stay as typed."""
    for template, pattern in _PATTERNS:
        found = pattern.fullmatch(message)
        if found is None:
            continue
        values = found.groupdict()
        if "message" in values:
            values["message"] = refusal(values["message"], language)
        return _SPEC.sub(lambda m: values[m.group(1) or "s"], language.gettext(template))
    return message


class LabHelpFormatter(argparse.HelpFormatter):
    """argparse's help layout with ``usage:`` in the command's language."""

    def __init__(self, prog: str, *, language: Language = ENGLISH, **kwargs: Any) -> None:
        super().__init__(prog, **kwargs)
        self.language = language

    def add_usage(
        self,
        usage: str | None,
        actions: Iterable[argparse.Action],
        groups: Iterable[argparse._MutuallyExclusiveGroup],
        prefix: str | None = None,
    ) -> None:
        if prefix is None:
            prefix = self.language.gettext("usage: ")
        super().add_usage(usage, actions, groups, prefix)


class LabParser(argparse.ArgumentParser):
    """An argument parser whose help and refusals speak ``language`` (its subcommands'
    parsers are made with the language given to ``add_parser``)."""

    def __init__(self, *args: Any, language: Language = ENGLISH, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", functools.partial(LabHelpFormatter, language=language))
        add_help = kwargs.pop("add_help", True)
        super().__init__(*args, add_help=False, **kwargs)
        self.language = language
        self._positionals.title = language.gettext("positional arguments")
        self._optionals.title = language.gettext("options")
        if add_help:
            self.add_argument(
                "-h",
                "--help",
                action="help",
                default=argparse.SUPPRESS,
                help=language.gettext("show this help message and exit"),
            )

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        text = self.language.gettext("{prog}: error: {message}").format(
            prog=self.prog, message=refusal(message, self.language)
        )
        self.exit(EXIT_USAGE, text + "\n")


def lang_option(argv: Sequence[str]) -> str | None:
    """The code ``--lang`` gives in ``argv`` (the last one, before any ``--``), read before
    the parser is built in its language."""
    code = None
    for k, arg in enumerate(argv):
        if arg == "--":
            break
        if arg == "--lang" and k + 1 < len(argv):
            code = argv[k + 1]
        elif arg.startswith("--lang="):
            code = arg.partition("=")[2]
    return code


__all__ = ["REFUSALS", "LabHelpFormatter", "LabParser", "lang_option", "refusal"]
