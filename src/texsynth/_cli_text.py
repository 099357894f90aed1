"""The command line's help text, generated from the functions' numpydoc docstrings (:mod:`texsynth.cli`).

An option's short help is the first sentence of its entry in the Parameters section (of the function or of
its option group's class); ``METHOD --help-full`` shows the whole text. Grouped entries (``a, b : ...``) and
"As in :func:`f`" references are resolved here.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import re
import sys

from .registry import group_fields, is_group

__all__ = ["doc_entries", "doc_params", "doc_sources", "full_doc", "signature_parameters", "group_heading",
           "plain_text", "short_help", "first_sentence", "HelpFull", "referenced_function", "did_you_mean",
           "REFERENCE", "ONLY_REFERENCE", "ABBREVIATIONS"]


def doc_entries(func):
    """The Parameters section of a numpydoc docstring as [(names, description)], one per entry."""
    doc = inspect.getdoc(func) or ""
    match = re.search(r"^Parameters\n-+\n(.*?)(?:^\w[\w ]*\n-+\n|\Z)", doc, re.S | re.M)
    entries = []
    if not match:
        return entries
    for line in match.group(1).splitlines():
        if line and not line.startswith(" "):
            names = line.split(":")[0]
            entries.append(([n.strip() for n in names.split(",") if n.strip()], ""))
        elif entries and line.strip():
            names, text = entries[-1]
            entries[-1] = (names, (text + " " + line.strip()).strip())
    return entries


REFERENCE = re.compile(r"^As in :(?:func|meth):`~?([\w.]+)`")


ONLY_REFERENCE = re.compile(r"^As in :(?:func|meth):`~?[\w.]+`\.?$")  # nothing but the pointer


def referenced_function(func, text):
    """The function a description such as "As in :func:`optimize_texture`, ..." refers to, or None.

    A bare name is looked up in the module of ``func``, then among texsynth's public names.
    """
    match = REFERENCE.match(text)
    if not match:
        return None
    module_name, _, name = match.group(1).rpartition(".")
    try:
        module = importlib.import_module(module_name) if module_name else sys.modules[func.__module__]
    except (ImportError, KeyError):
        return None
    other = getattr(module, name, None)
    if other is None and not module_name:
        try:
            other = getattr(importlib.import_module("texsynth"), name, None)
        except ImportError:
            return None
    return other if callable(other) and other is not func else None


def doc_sources(obj):
    """The Parameters entries of ``obj``'s docstring and, for a function, those of its option groups' classes."""
    entries = list(doc_entries(obj))
    for param in signature_parameters(obj).values():
        if is_group(param.default):
            entries += doc_entries(type(param.default))
    return entries


def signature_parameters(obj):
    """The parameters of a function's signature ({} for a class or what has no signature)."""
    if isinstance(obj, type):
        return {}
    try:
        return inspect.signature(obj).parameters
    except (TypeError, ValueError):
        return {}


def group_heading(pname, default):
    """The --help heading of an option group's flags: ``search=Search(...)``."""
    return f"{pname}={type(default).__name__}(...)"


def full_doc(obj, seen=()):
    """{name: description} of ``obj``'s parameters (and its groups' fields), each complete on its own.

    A grouped entry's description goes to each of its names, after the name's
    own description from the function the entry refers to ("As in
    :func:`inpaint`"), itself complete; a bare "As in ..." is dropped where
    the name has its own. No description points to another option: these
    are what another function's grouped entry borrows.
    """
    out = {}
    for names, text in doc_sources(obj):
        other = referenced_function(obj, text)
        own = full_doc(other, seen + (obj,)) if other is not None and other not in seen else {}
        for n in names:
            mine = own.get(n, "")
            out[n] = mine if mine and ONLY_REFERENCE.match(text) else f"{mine} {text}".strip()
    return out


def doc_params(func, shown=None):
    """Option descriptions from a numpydoc docstring: {name: description}.

    The function's Parameters section, and for each option group (a
    parameter whose default is a dataclass instance) the Parameters section
    of the group's class, one entry per field. A grouped entry (``a, b, c :
    type`` with one description for all) gives its description to the
    first of its names that is ``shown`` as an option; the others get "see
    --first" instead of a copy of the same sentence. When the description
    refers to another function ("As in :func:`optimize_texture`, ..."),
    every name also gets its own, complete description from that function's
    docstring (a bare "As in ..." is then left out); a name whose
    description is the same as an option shown before it gets "See
    --that-option." instead of a copy.
    """
    out = {}
    carrier = {}  # a borrowed description -> the shown option that carries it
    groups = {pname: group_heading(pname, param.default) for pname, param in signature_parameters(func).items()
              if is_group(param.default) and (shown is None or any(
                  field.name in shown for field in group_fields(param.default)))}  # the headings of their flags

    def flag(name):
        return groups.get(name) or "--" + name.replace("_", "-")

    for names, text in doc_sources(func):
        other = referenced_function(func, text)
        own = full_doc(other, (func,)) if other is not None else {}
        visible = [n for n in names if shown is None or n in shown or n in groups]
        first = (visible or names)[0]
        bare = bool(ONLY_REFERENCE.match(text))
        for n in names:
            mine = own.get(n, "")
            if mine in carrier:
                out[n] = f"See {flag(carrier[mine])}."
                continue
            if mine and n in visible:
                carrier[mine] = n
            if n == first:
                out[n] = mine if mine and bare else f"{mine} {text}".strip()
            elif mine and bare:  # its own description says it all
                out[n] = mine
            else:
                out[n] = f"{mine} (see {flag(first)})" if mine else f"See {flag(first)}."
    return out


def plain_text(text):
    """numpydoc markup to plain help text: ``x`` -> x, :func:`~a.f` -> f()."""
    text = re.sub(r":(?:func|meth):`~?(?:[\w]+\.)*(\w+)`", r"\1()", text)
    text = re.sub(r":\w+:`~?([^`]+)`", r"\1", text)
    text = re.sub(r"\s*\[\d+\]_", "", text)  # citations of the References section: [2]_
    return text.replace("``", "")


class HelpFull(argparse.Action):
    """``--help-full``: the help with every option's full description (``--help`` shows the first sentence)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None, full=None):
        super().__init__(option_strings, dest, nargs=0, default=default, help=help)
        self.full = full

    def __call__(self, parser, namespace, values, option_string=None):
        for item, (attribute, text) in self.full.items():
            setattr(item, attribute, text)
        parser.print_help()
        parser.exit()


def short_help(text):
    """An option's help on ``--help``: the first sentence of its description, without pointers to the Python
    docstring's sections ("see Notes")."""
    text = first_sentence(text)
    text = re.sub(r"\s*\((?:see|the) Notes[^()]*\)|[;,]\s*see Notes\b|\s*\(see Notes\s+and[^()]*\)", "", text)
    return text.replace(" ,", ",").strip()


ABBREVIATIONS = ("e.g.", "i.e.", "et al.", "etc.", "cf.", "vs.", "approx.", "resp.", "Sec.", "Fig.", "Eq.", "eq.",
                  "Ch.", "no.", "Nos.", "al.")


def first_sentence(text):
    """The first sentence of a description: up to the first full stop outside brackets that is followed by a
    space (or ends the text); abbreviations such as "e.g." and "et al." do not end one, nor do the dots of
    numbers and dotted names (0.5, texsynth.core).

    >>> first_sentence('Levels of the pyramid (e.g. 3). "auto": as many as fit.')
    'Levels of the pyramid (e.g. 3).'
    >>> first_sentence("Weight 0.5 of Kwatra et al. 2005. More.")
    'Weight 0.5 of Kwatra et al. 2005.'
    """
    depth = 0
    for i, char in enumerate(text):
        if char in "([{":
            depth += 1
        elif char in ")]}":
            depth = max(0, depth - 1)
        elif char == "." and depth == 0:
            rest = text[i + 1:]
            if not rest.strip():
                return text.strip()
            if not rest[0].isspace() or any(text[: i + 1].endswith((" " + a, "(" + a)) or text[: i + 1] == a
                                            for a in ABBREVIATIONS):
                continue
            return text[: i + 1].strip()
    return text.strip()


def did_you_mean(message):
    """argparse's "invalid choice: 'X' (choose from ...)" with the likeliest choices named first.

    A choice that shares a dash-separated word with X comes first (``pixels`` -> ``synthesize-pixels``,
    ``seam-carve`` -> ``carve-seams``), else the closest spellings (``quilts`` -> ``quilt``).
    """
    import difflib

    match = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)$", message)
    if not match:
        return message
    given, choices = match.group(1), re.findall(r"'([^']*)'", match.group(2))
    words = set(given.lower().split("-")) - {""}
    likely = [c for c in choices if words & set(c.split("-"))] or difflib.get_close_matches(given, choices, 3, 0.6)
    if not likely:
        return message
    names = " or ".join(repr(c) for c in likely[:3])
    return message.replace(" (choose from ", f"; did you mean {names}? (choose from ", 1)
