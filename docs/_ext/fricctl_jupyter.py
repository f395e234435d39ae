"""A chapter's executed notebook as plain Jupyter shows it: the ``.ipynb`` a reader downloads.

The book reads a chapter's markdown as MyST: ``{eq}`eq-motion``` and ``{numref}`fig-x```
(made from the chapter's links by ``fricctl_book.cross_references``), a labelled equation
``$$ ... $$ (eq-motion)``, links to the API (``[`simulate`](#fricctl.simulate.simulate)``) and
to the bibliography (``[Gervini et al. 2003](#gervini2003)``), which Sphinx resolves; roles such
as ``{py:func}`` or ``{cite}`` and directives (```` ```{admonition} ````, ``:::{dropdown}``)
would be read the same way.  Jupyter knows none of them: it would show the markup, and every
such link would be dead.  :func:`jupyter_notebook` gives the notebook whose markdown cells say
what the book's page says in what Jupyter renders (issue 24):

* an equation gets the number the book shows (``\\tag{5.3}``), a labelled one its anchor
  (``<a id="eq-motion"></a>``) too; a reference to it reads ``[Eq. (5.3)](#eq-motion)``;
* a captioned figure gets its caption under it, numbered as in the book ("**Fig. 5.2.** ..."),
  in a markdown cell of its own (anchored by the figure's name), so ``[Fig. 5.2](#fig-x)`` links;
* a citation reads as the book's, ``[Gervini et al., 2003](#gervini2003)``, and links to the
  notebook's last cell, "Works cited", which gives each cited work in full (from the ``.bib``);
* an API link becomes its words (``code``): the reference is the book's, not the notebook's;
  a link to another chapter names its ``.ipynb`` (beside this one when downloaded together),
  a link to another page of the book becomes its words;
* a directive becomes Markdown: an admonition a blockquote with a bold title, a dropdown's
  content a plain section under its bold title, a ``{math}`` block a ``$$`` equation;
  any other role its text;
* a cell the book collapses (``hide-cell``, ``hide-input``) is collapsed in JupyterLab too
  (``metadata.jupyter.source_hidden``).

The code cells' sources and outputs are not touched; the cells added (captions, works cited)
are tagged :data:`ADDED`, so that a reader of the notebook (``make book-pdf``) can drop them.
Nothing here imports Sphinx: ``fricctl_book.notebook_download`` gathers the numbers.
"""

from __future__ import annotations

import copy
import re
from typing import Mapping, Sequence

#: The tag of the markdown cells this module adds (figure captions, works cited).
ADDED = "fricctl-jupyter"

#: A MyST role, ``{name}`text```: what must not be left in a downloaded notebook.
ROLE = re.compile(r"\{([A-Za-z][\w:.+-]*)\}`([^`]*)`")
#: The opening line of a MyST directive, ```` ```{name} args ```` or ``:::{name} args``.
DIRECTIVE = re.compile(r"^([ \t]*)(`{3,}|~{3,}|:{3,})\{([\w:.-]+)\}[ \t]*(.*)$")
#: A display equation, with the label MyST writes after it: ``$$ ... $$ (eq-motion)``.
_DISPLAY = re.compile(r"\$\$(.+?)\$\$(?:[ \t]*\(([\w-]+)\))?", re.S)
#: An amsmath environment at the start of a line, which MyST's amsmath reads as display math.
_AMSMATH = re.compile(r"^\\begin\{(equation|multline|gather|align|alignat|flalign)\*?\}.*?"
                      r"^\\end\{\1\*?\}", re.S | re.M)
#: A Markdown link ``[words](target)``.
_LINK = re.compile(r"\[((?:[^\[\]]|\[[^\]]*\])*)\]\(([^()\s]*(?:\([^()]*\)[^()\s]*)*)\)")
#: A scheme (``https:``, ``mailto:``): a link that works anywhere.
_SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")
#: A link to a chapter, ``05_open_loop_compensation_and_dead_zone`` (``.py``/``.ipynb``/``.md``).
_CHAPTER = re.compile(r"^(?:\./)?(\d\d_\w+?)(?:\.(?:py|ipynb|md))?(#[\w-]*)?$")

#: Admonitions, titled by their name when they have no title of their own.
_ADMONITIONS = {"note", "tip", "hint", "important", "warning", "caution", "attention", "danger",
                "error", "seealso", "admonition", "margin", "sidebar", "topic", "epigraph"}
#: Directives whose content is shown as a plain section (their title bold above it).
_SECTIONS = {"dropdown", "toggle", "solution", "exercise", "card", "tab-item", "div", "container"}


def cite_label(entry) -> str:
    """How the book cites a pybtex ``entry`` (sphinxcontrib-bibtex's author-year style):
    ``Gervini et al., 2003``, ``Savitzky and Golay, 1964``, ``Ljung, 1999``."""
    from pybtex.richtext import Text

    people = entry.persons.get("author") or entry.persons.get("editor") or []
    names = [Text.from_latex(" ".join(p.prelast_names + p.last_names)).render_as("text")
             for p in people]
    who = (names[0] if len(names) == 1 else " and ".join(names) if len(names) == 2
           else f"{names[0]} et al." if names else entry.key)
    return f"{who}, {entry.fields.get('year', 'n.d.')}"


def citations(bibfiles: Sequence) -> dict[str, tuple[str, str]]:
    """Every entry of ``bibfiles``: key -> (how the book cites it, the full reference in
    Markdown, pybtex's ``plain`` style as sphinxcontrib-bibtex's bibliography page lists it)."""
    from pybtex.database import BibliographyData, parse_file
    from pybtex.plugin import find_plugin

    data = BibliographyData()
    for path in bibfiles:
        for key, entry in parse_file(str(path)).entries.items():
            data.add_entry(key, entry)
    style = find_plugin("pybtex.style.formatting", "plain")()
    out = {}
    for formatted in style.format_entries(list(data.entries.values())):
        full = re.sub(r"\s+", " ", formatted.text.render_as("markdown")).strip()
        out[formatted.key] = (cite_label(data.entries[formatted.key]), full)
    return out


def _directives(text: str) -> str:
    """``text`` with each MyST directive (outside plain code fences) made Markdown, nested
    ones too."""
    lines = text.split("\n")
    out: list[str] = []
    i = 0
    while i < len(lines):
        line = lines[i]
        fence = re.match(r"^[ \t]*(`{3,}|~{3,})(?!.*\{)", line)
        if fence:  # a plain code fence: copied as it is, to its end
            j = i + 1
            while j < len(lines) and not lines[j].strip().startswith(fence.group(1)):
                j += 1
            out += lines[i:j + 1]
            i = j + 1
            continue
        m = DIRECTIVE.match(line)
        if not m:
            out.append(line)
            i += 1
            continue
        indent, marker, name, args = m.groups()
        j, depth = i + 1, 1
        while j < len(lines):  # the fence that closes this one (nested ones of its kind counted)
            s = lines[j].strip()
            if DIRECTIVE.match(lines[j]) and s.startswith(marker[0] * len(marker)):
                inner = DIRECTIVE.match(lines[j]).group(2)
                if inner == marker:
                    depth += 1
            elif s and set(s) == {marker[0]} and len(s) >= len(marker):
                depth -= 1
                if depth == 0:
                    break
            j += 1
        body = lines[i + 1:j]
        options = {}
        while body and re.match(r"^[ \t]*:[\w-]+:", body[0]):
            key, _, value = body.pop(0).strip()[1:].partition(":")
            options[key] = value.strip()
        while body and body[0].strip().startswith("---"):  # YAML options block
            end = next((k for k in range(1, len(body)) if body[k].strip() == "---"), 0)
            body = body[end + 1:]
        content = _directives("\n".join(body)).strip("\n")
        out += [indent + ln for ln in _directive_markdown(name.split(":")[-1], args.strip(),
                                                          options, content).split("\n")]
        i = j + 1
    return "\n".join(out)


def _directive_markdown(name: str, args: str, options: dict, content: str) -> str:
    """One directive as Markdown (:func:`_directives`)."""
    if name == "math":
        label = options.get("label")  # anchored when numbered (_number_equations)
        return f"$$\n{content}\n$$" + (f" ({label})" if label else "")
    if name in _SECTIONS:
        title = args or name.capitalize()
        return f"**{title}**\n\n{content}"
    if name in ("code-block", "code", "code-cell", "sourcecode"):
        return f"```{args}\n{content}\n```"
    if name in ("figure", "image"):
        alt = options.get("alt", "")
        return f"![{alt}]({args})" + (f"\n\n*{content}*" if content else "")
    if name in ("only", "raw", "toctree", "bibliography", "glossary"):
        return ""  # builder-specific (or the book's navigation): nothing a notebook shows
    title = args if name in ("admonition", "topic", "sidebar") and args else (
        name.capitalize() + (f": {args}" if args else ""))
    quoted = "\n".join(f"> {ln}" if ln.strip() else ">" for ln in content.split("\n"))
    return f"> **{title}**\n>\n{quoted}"


def jupyter_markdown(text: str, *, numbers: Mapping[str, str], anchored: set,
                     cites: Mapping[str, tuple[str, str]], cited: list,
                     equations: list | None = None) -> str:
    """One markdown cell as Jupyter shows it (the module's docstring says what changes).

    Parameters
    ----------
    text : str
        The cell's MyST source.
    numbers : mapping
        A label's number as the book shows it: ``"eq-motion" -> "Eq. (5.3)"``,
        ``"fig-loop" -> "Fig. 5.2"``.
    anchored : set
        The labels that have an anchor in this notebook (a reference to one links to it).
    cites : mapping
        Bibliography key -> (citation as the book shows it, full reference) (:func:`citations`).
    cited : list
        The keys cited so far, in order; appended to.
    equations : list or None
        The numbers of the notebook's display equations still to come, in order ("5.3"); each
        equation of this cell takes the first.  None: the equations are not numbered.
    """
    def convert(t: str) -> str:
        return _roles_and_links(t, numbers=numbers, anchored=anchored, cites=cites, cited=cited)

    text = _directives(text)
    text = _number_equations(text, equations)
    return _outside_code(text, convert)


def _outside_code(text: str, convert) -> str:
    """``convert`` applied to ``text`` outside its code fences and inline code spans, a role's
    own backticks excepted (``{eq}`x``` is a role, not a code span)."""
    out, pos = [], 0
    for m in re.finditer(r"^[ \t]*(`{3,}|~{3,})[^\n]*\n.*?^[ \t]*\1[ \t]*$", text, re.S | re.M):
        out.append(_outside_spans(text[pos:m.start()], convert))
        out.append(m.group(0))
        pos = m.end()
    out.append(_outside_spans(text[pos:], convert))
    return "".join(out)


def _outside_spans(text: str, convert) -> str:
    # a role's backticks are taken first (its text is rendered by convert); then code spans
    pieces = re.split(r"(\{[A-Za-z][\w:.+-]*\}`[^`]*`|(?<!`)`[^`\n]+`(?!`))", text)
    out = []
    buffer = ""
    for k, piece in enumerate(pieces):
        if k % 2 == 1 and not piece.startswith("{"):
            # a code span: kept, but a link around it ([`simulate`](#fricctl...)) must still
            # be seen whole -- so spans are protected by a placeholder, not split off
            buffer += f"\x00{len(out)}\x00"
            out.append(piece)
        else:
            buffer += piece
    converted = re.sub(r"\x00(\d+)\x00", lambda m: out[int(m.group(1))], convert(buffer))
    # a link's code words and the code after it ([`simulate`](#fricctl...)`(...)`), one span
    # once the link is gone: `simulate(...)`, not `simulate``(...)`
    return re.sub(r"(?<!`)`([^`\n]+)``([^`\n]+)`(?!`)", r"`\1\2`", converted)


def _number_equations(text: str, equations: list | None) -> str:
    """Each display equation of ``text`` with its number (``\\tag``) and, if labelled, an
    anchor before it; an amsmath environment takes its number from ``equations`` too, unshown
    (its lines would each need their own)."""
    found = sorted([(m.start(), m.end(), "dollar", m) for m in _DISPLAY.finditer(text)]
                   + [(m.start(), m.end(), "ams", m) for m in _AMSMATH.finditer(text)
                      if not any(d.start() <= m.start() < d.end() for d in _DISPLAY.finditer(text))],
                   key=lambda x: x[0])
    out, pos = [], 0
    for start, end, kind, m in found:
        number = None  # None also where the book shows no number
        if equations is not None:
            if not equations:
                raise ValueError("more display equations in the notebook's markdown than on "
                                 "the book's page")
            number = equations.pop(0)
        out.append(text[pos:start])
        if kind == "dollar":
            body, label = m.group(1), m.group(2)
            tag = "" if number is None or re.search(r"\\(tag|notag|nonumber)\b", body) else (
                f" \\tag{{{number}}}")
            anchor = f'<a id="{label}"></a>\n\n' if label else ""
            end_space = body[len(body.rstrip()):]  # "$$\n...\n$$" keeps its closing line
            out.append(f"{anchor}$${body.rstrip()}{tag}{end_space or (' ' if tag else '')}$$")
        else:
            out.append(m.group(0))
        pos = end
    out.append(text[pos:])
    return "".join(out)


#: A role or a link: one pass, so that the works are cited in the order the text cites them.
_ROLE_OR_LINK = re.compile(f"{ROLE.pattern}|{_LINK.pattern}")


def _roles_and_links(text: str, *, numbers, anchored, cites, cited) -> str:
    def role(name, content):
        short = name.split(":")[-1]
        target = re.search(r"<([^<>]+)>\s*$", content)
        words = content[:target.start()].strip() if target else None
        label = target.group(1) if target else content.strip()
        if short in ("eq", "numref", "ref", "numfig") and label in numbers:
            shown = numbers[label] if short in ("eq", "numref") or not words else words
            return f"[{shown}](#{label})" if label in anchored else shown
        if short in ("eq", "numref"):
            raise ValueError(f"{{{name}}}`{content}`: no number for {label!r}")
        if short in ("cite", "cite:p", "cite:t", "p", "t", "ps", "ts", "cite:ps", "cite:ts"):
            keys = [k.strip() for k in label.split(",") if k.strip()]
            return "(" + "; ".join(_cite(k, cites, cited) for k in keys) + ")"
        if short in ("doc", "ref", "any", "term", "download"):
            return words or label.split("/")[-1].removeprefix("~")
        # {py:func}`fricctl.simulate.simulate`, {math}`x`, {sub-ref}, ...: its text
        if short == "math":
            return f"${content}$"
        shown = words or label.removeprefix("~").removeprefix("!")
        return f"`{shown}`"

    def link(whole, words, target):
        if _SCHEME.match(target):
            return whole
        if target.startswith("#"):
            key = target[1:]
            if key in cites:
                return _cite(key, cites, cited)
            if key.startswith("fricctl"):  # the API reference: the book's, not the notebook's
                return words
            return whole  # a heading or an anchor of the notebook
        chapter = _CHAPTER.match(target)
        if chapter:
            return f"[{words}]({chapter.group(1)}.ipynb{chapter.group(2) or ''})"
        if re.search(r"\.(png|jpe?g|svg|gif)$", target, re.I):
            return whole
        return words  # another page of the book: its words

    return _ROLE_OR_LINK.sub(lambda m: role(m.group(1), m.group(2)) if m.group(1) is not None
                             else link(m.group(0), m.group(3), m.group(4)), text)


def _cite(key: str, cites, cited: list) -> str:
    if key not in cites:
        raise ValueError(f"citation {key!r} is not in the bibliography")
    if key not in cited:
        cited.append(key)
    return f"[{cites[key][0]}](#{key})"


def jupyter_notebook(nb, *, numbers: Mapping[str, str], equations: Sequence[str],
                     figures: Mapping[int, Sequence[str]], cites: Mapping[str, tuple[str, str]]):
    """A copy of the executed notebook ``nb`` whose markdown reads in plain Jupyter as the
    book's page reads (the module's docstring); code and outputs unchanged.

    Parameters
    ----------
    nb : nbformat.NotebookNode
        The notebook the book rendered (myst-nb's output notebook).
    numbers : mapping
        Every label's number as the book shows it, ``"Eq. (5.3)"``, ``"Fig. 5.2"``.
    equations : sequence of str or None
        The numbers of this page's display equations, in page order (None: one the book does
        not number); one per equation of the markdown cells, else ValueError (a number would go
        to the wrong equation).
    figures : mapping
        A code cell's index -> the numbers of the captioned figures among its outputs ("5.2").
    cites : mapping
        :func:`citations`.
    """
    nb = copy.deepcopy(nb)
    anchored = {m.group(2) for c in nb.cells if c.cell_type == "markdown"
                for m in _DISPLAY.finditer(c.source) if m.group(2)}
    for index, cell in enumerate(nb.cells):
        name = cell.metadata.get("mystnb", {}).get("figure", {}).get("name")
        if name and figures.get(index):
            anchored.add(name)
    pending = list(equations)
    cited: list[str] = []
    out = []
    import nbformat

    for index, cell in enumerate(nb.cells):
        out.append(cell)
        if cell.cell_type == "markdown":
            cell.source = jupyter_markdown(cell.source, numbers=numbers, anchored=anchored,
                                           cites=cites, cited=cited, equations=pending)
            continue
        tags = cell.metadata.get("tags", [])
        if {"hide-cell", "hide-input"} & set(tags):
            cell.metadata.setdefault("jupyter", {})["source_hidden"] = True
        if "hide-cell" in tags or "hide-output" in tags:
            cell.metadata.setdefault("jupyter", {})["outputs_hidden"] = True
        figure = cell.metadata.get("mystnb", {}).get("figure", {})
        shown = figures.get(index)
        if cell.cell_type != "code" or not shown or not figure.get("caption"):
            continue
        caption = jupyter_markdown(figure["caption"], numbers=numbers, anchored=anchored,
                                   cites=cites, cited=cited)
        head = (f"Fig. {shown[0]}" if len(shown) == 1 else
                "Figs. " + ", ".join(shown[:-1]) + f" and {shown[-1]}")
        anchor = f'<a id="{figure["name"]}"></a>' if figure.get("name") else ""
        added = nbformat.v4.new_markdown_cell(f"{anchor}**{head}.** {caption}")
        added.metadata["tags"] = [ADDED]
        out.append(added)
    if pending:
        raise ValueError(f"the book numbered {len(pending)} display equation(s) more than the "
                         f"notebook's markdown holds")
    if cited:
        works = "\n".join(f'* <a id="{k}"></a>{cites[k][1]}' for k in cited)
        added = nbformat.v4.new_markdown_cell(f"## Works cited\n\n{works}")
        added.metadata["tags"] = [ADDED]
        out.append(added)
    nb.cells = out
    return nb
