"""The book (``make book``, ``docs/conf.py``) as a reader sees it.

The book is built once per session in fast mode (``FRICCTL_FAST=1``) into a temporary
folder with the flags of ``make book`` (``-E -W --keep-going``: a cell error or any Sphinx
warning fails the build), or taken from ``FRICCTL_BOOK_HTML`` when that names a book built
by ``FRICCTL_FAST=1 make book`` (what ``.ci/run`` does, so that CI builds it once, through the
Makefile).  A fast build executes every chapter and a short ``fricctl reproduce``: minutes,
hence the ``slow`` marker.

The HTML checks parse the pages (every chapter has its page, every ``<img>`` resolves to a
file, no error output, solutions collapsed and widget cells replaced, the API reference
there, nothing loaded from another host); the browser check opens pages in a real headless
Chromium (Debian's ``chromium`` + ``chromium-driver``; skipped with the reason where they are
not installed) and asserts every image decoded (``naturalWidth > 0``) and every equation
typeset by MathJax without a TeX error.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

ROOT = Path(__file__).resolve().parent.parent
CHAPTERS = sorted((ROOT / "chapters").glob("[0-9][0-9]_*.py"))
API_PAGES = sorted(p.stem for p in (ROOT / "docs" / "api").glob("*.md") if p.stem != "index")
CHROMIUM = Path("/usr/bin/chromium")
CHROMEDRIVER = Path("/usr/bin/chromedriver")

pytestmark = pytest.mark.slow


# -- the build -------------------------------------------------------------------------------

@pytest.fixture(scope="session")
def book(tmp_path_factory) -> Path:
    """The HTML folder of a fast build of the book."""
    given = os.environ.get("FRICCTL_BOOK_HTML")
    if given:
        html = Path(given).resolve()
        assert (html / "index.html").is_file(), f"FRICCTL_BOOK_HTML={given} holds no index.html"
        return html
    for module in ("sphinx", "myst_nb", "sphinx_book_theme", "numpydoc", "ipykernel"):
        pytest.importorskip(module, reason="the book needs: pip install -e '.[book]'")
    tmp = tmp_path_factory.mktemp("book")
    cmd = [sys.executable, "-m", "sphinx", "-b", "html", "-E", "-W", "--keep-going", "-T",
           "-d", str(tmp / "doctrees"), "-D", f"fricctl_reproduce_dir={tmp / 'reproduce'}",
           str(ROOT / "docs"), str(tmp / "html")]
    env = dict(os.environ, FRICCTL_FAST="1")
    # no timeout: the build's length depends on the machine's load (CI's job limit finds a hang)
    proc = subprocess.run(cmd, cwd=tmp, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        out = proc.stdout + proc.stderr
        cell = out.find("CellExecutionError")  # a chapter's cell failed: show that cell's error
        pytest.fail(f"the book's build exited with {proc.returncode}\n--- output (tail)\n"
                    f"{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
                    + (f"\n--- the failing cell\n{out[cell:cell + 8000]}" if cell >= 0 else ""))
    return tmp / "html"


class _Page(HTMLParser):
    """The parts of a page the checks read: tags with their attributes, ``<pre>`` texts,
    the class lists of the ``div``s, and the whole text; and each ``<img>`` with the
    ``<figure>`` around it (``images``: attributes and an index into ``captions``, the text of
    each figure's ``<figcaption>``, None for a figure without one)."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.tags: list[tuple[str, dict]] = []
        self.pres: list[str] = []
        self.text: list[str] = []
        self.images: list[tuple[dict, int | None]] = []
        self.captions: list[str | None] = []
        self._pre = 0
        self._figures: list[int] = []  # the figures open here, innermost last
        self._caption: int | None = None  # the figure whose <figcaption> is open

    def handle_starttag(self, tag, attrs):
        attrs = {k: (v or "") for k, v in attrs}
        self.tags.append((tag, attrs))
        if tag == "pre":
            self._pre += 1
            self.pres.append("")
        elif tag == "figure":
            self._figures.append(len(self.captions))
            self.captions.append(None)
        elif tag == "figcaption" and self._figures:
            self._caption = self._figures[-1]
            self.captions[self._caption] = ""
        elif tag == "img":
            self.images.append((attrs, self._figures[-1] if self._figures else None))

    def handle_endtag(self, tag):
        if tag == "pre" and self._pre:
            self._pre -= 1
        elif tag == "figcaption":
            self._caption = None
        elif tag == "figure" and self._figures:
            self._figures.pop()

    def handle_data(self, data):
        self.text.append(data)
        if self._pre:
            self.pres[-1] += data
        if self._caption is not None:
            self.captions[self._caption] += data

    def find(self, tag: str, cls: str | None = None) -> list[dict]:
        return [a for t, a in self.tags
                if t == tag and (cls is None or cls in a.get("class", "").split())]


def parse(path: Path) -> _Page:
    page = _Page()
    page.feed(path.read_text(encoding="utf-8"))
    return page


def _pages(book: Path) -> list[Path]:
    return sorted(p for p in book.rglob("*.html") if "_static" not in p.parts)


# -- the HTML --------------------------------------------------------------------------------

def test_every_chapter_has_a_page_in_the_navigation(book):
    assert CHAPTERS, "no chapter found"
    nav = {a.get("href", "").split("#")[0] for a in parse(book / "index.html").find("a")}
    for chapter in CHAPTERS:
        page = book / "chapters" / f"{chapter.stem}.html"
        assert page.is_file(), f"no page for {chapter.name}"
        assert f"chapters/{chapter.stem}.html" in nav, f"{chapter.name} is not in the navigation"
    for page in ("reproduction.html", "notation.html", "api/index.html"):
        assert (book / page).is_file(), f"no {page}"


def test_every_chapter_downloads_as_an_executed_notebook(book):
    """The download menu of each chapter offers the executed ``.ipynb`` (issue 24) beside the
    jupytext ``.py``; both links resolve, and the notebook holds the chapter's outputs."""
    import json

    for chapter in CHAPTERS:
        page = book / "chapters" / f"{chapter.stem}.html"
        links = {unquote(urlsplit(a.get("href", "")).path) for a in parse(page).find("a")}
        for suffix in (".ipynb", ".py"):
            link = next((h for h in links if h.endswith(f"_sources/chapters/{chapter.stem}{suffix}")),
                        None)
            assert link, f"{page.name}: no {suffix} download"
            assert (page.parent / link).resolve().is_file(), f"{page.name}: {link} missing"
        nb = json.loads((book / "_sources" / "chapters" / f"{chapter.stem}.ipynb").read_text())
        code = [c for c in nb["cells"] if c["cell_type"] == "code"]
        assert nb["nbformat"] == 4 and code and sum(bool(c.get("outputs")) for c in code) > 0


#: What Jupyter would show raw in a markdown cell: a MyST role (``{eq}`x```, ``{py:func}`f```,
#: not a code span that mentions one), a directive's fence, a MyST equation label, a link to the
#: API or the bibliography by an anchor the notebook does not have.
_RAW_MYST = re.compile(r"(?<!`)\{[A-Za-z][\w:.+-]*\}`|^[ \t]*(?:`{3,}|~{3,}|:{3,})\{|\$\$[ \t]*\([\w-]+\)",
                       re.M)


def _without_code_fences(text: str) -> str:
    return re.sub(r"^[ \t]*(`{3,}|~{3,})(?!\{)[^\n]*\n.*?^[ \t]*\1[ \t]*$", "", text, flags=re.S | re.M)


def test_the_downloaded_notebooks_read_in_jupyter_as_the_page_reads(book):
    """Each chapter's ``.ipynb`` is a valid notebook (nbformat) with the page's code and
    outputs, and its markdown is what plain Jupyter renders (issue 24): no MyST role, directive
    or equation label left; its display equations carry the page's numbers (``\\tag``), in
    page order; each figure's caption follows it with the page's number; every in-notebook link
    (``#eq-``, ``#fig-``, a citation) has its anchor; the works cited are listed."""
    nbformat = pytest.importorskip("nbformat")
    figures_total = 0
    for chapter in CHAPTERS:
        path = book / "_sources" / "chapters" / f"{chapter.stem}.ipynb"
        nb = nbformat.read(path, as_version=4)
        nbformat.validate(nb)
        markdown = [c.source for c in nb.cells if c.cell_type == "markdown"]
        for source in markdown:
            raw = _RAW_MYST.findall(_without_code_fences(source))
            assert not raw, f"{path.name}: MyST markup left in a markdown cell: {raw[:3]}"
        text = "\n".join(markdown)
        page = book / "chapters" / f"{chapter.stem}.html"
        assert re.findall(r"\\tag\{([^}]*)\}", text) == _eqnos(page), f"{path.name}: equation numbers"
        captions = re.findall(r"^(?:<a id=\"[^\"]+\"></a>)?\*\*Figs?\. ([\d., and]+)\.\*\*", text, re.M)
        numbers = [n for c in captions for n in re.split(r", | and ", c)]
        shown = [re.match(r"\s*Fig\. (\d+\.\d+)", parse(page).captions[f]).group(1)
                 for _, f in parse(page).images if f is not None]
        assert numbers == list(dict.fromkeys(shown)), f"{path.name}: figure numbers {numbers} vs {shown}"
        figures_total += len(numbers)
        anchors = set(re.findall(r'<a id="([^"]+)"></a>', text))
        for target in re.findall(r"\]\(#([^)\s]+)\)", text):
            if target.startswith(("eq-", "fig-")) or target[0].islower() and "-" not in target:
                assert target in anchors, f"{path.name}: a link to #{target}, which it lacks"
        assert "](#fricctl" not in text, f"{path.name}: a link to the API by an anchor"
        if "bibtex-citation" in page.read_text(encoding="utf-8"):
            assert "## Works cited" in text, f"{path.name}: cites, lists no works"
        # the code is the chapter's, cell for cell (the added cells are markdown)
        chapter_code = [c.source for c in _chapter_notebook(chapter).cells if c.cell_type == "code"]
        assert [c.source for c in nb.cells if c.cell_type == "code"] == chapter_code, path.name
    assert figures_total > 20


def _chapter_notebook(chapter: Path):
    jupytext = pytest.importorskip("jupytext")
    return jupytext.read(chapter, fmt="py:percent")


def test_a_notebook_for_jupyter_keeps_code_and_outputs_and_drops_the_markup():
    """fricctl_jupyter.jupyter_notebook on a made-up notebook: every kind of MyST markup the
    book reads becomes what Jupyter renders, with the numbers given; code, outputs and a role
    quoted in code are left as they are; an equation more or fewer than numbered is an error."""
    nbformat = pytest.importorskip("nbformat")
    pytest.importorskip("pybtex")
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import fricctl_jupyter as fj

    cites = fj.citations([ROOT / "docs" / "references.bib"])
    md = ("As {eq}`eq-x` and {numref}`fig-a` show ([Gervini, Gomes & da Rosa 2003](#gervini2003); "
          "{cite}`ljung1999`), [`simulate`](#fricctl.simulate.simulate)`(...)` in "
          "[Chapter 6](06_gain_design_and_closed_loop) and on the [notation page](../notation); "
          "{py:func}`fricctl.design.design_p`; `{eq}` quoted.\n\n"
          "$$ I\\,\\ddot q = T_m $$ (eq-x)\n\n$$\nb = 0\n$$\n\n"
          "```{admonition} Careful\n:class: tip\nSee {eq}`eq-x`.\n```\n\n"
          ":::{dropdown} Solution\nThe answer.\n:::\n\n```python\nx = 1  # {eq}`kept`\n```\n")
    plot = nbformat.v4.new_code_cell("plot()  # {eq}`not-markdown`")
    plot.outputs = [nbformat.v4.new_output("stream", name="stdout", text="{numref}`out`\n")]
    plot.metadata["mystnb"] = {"figure": {"caption": "The loop of $T_m$.", "name": "fig-a"}}
    plot.metadata["tags"] = ["hide-input"]
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_markdown_cell(md), plot])
    numbers = {"eq-x": "Eq. (5.1)", "fig-a": "Fig. 5.1"}
    out = fj.jupyter_notebook(nb, numbers=numbers, equations=["5.1", "5.2"], figures={1: ["5.1"]},
                              cites=cites)
    nbformat.validate(out)
    text = out.cells[0].source
    assert "[Eq. (5.1)](#eq-x) and [Fig. 5.1](#fig-a) show" in text
    assert "([Gervini et al., 2003](#gervini2003); ([Ljung, 1999](#ljung1999)))" in text
    assert "`simulate(...)` in [Chapter 6](06_gain_design_and_closed_loop.ipynb) and on the notation page" in text
    assert "`fricctl.design.design_p`; `{eq}` quoted." in text
    assert '<a id="eq-x"></a>\n\n$$ I\\,\\ddot q = T_m \\tag{5.1} $$' in text
    assert "$$\nb = 0 \\tag{5.2}\n$$" in text
    assert "> **Careful**\n>\n> See [Eq. (5.1)](#eq-x)." in text
    assert "**Solution**\n\nThe answer." in text and ":::" not in text
    assert "```python\nx = 1  # {eq}`kept`\n```" in text  # code in the prose is code
    assert not _RAW_MYST.findall(_without_code_fences(text)), text
    assert out.cells[1] == {**plot, "metadata": {**plot.metadata, "jupyter": {"source_hidden": True}}}
    assert out.cells[2].source == '<a id="fig-a"></a>**Fig. 5.1.** The loop of $T_m$.'
    assert out.cells[3].source.startswith("## Works cited\n\n* <a id=\"gervini2003\"></a>Gervini, Gomes")
    assert all(fj.ADDED in c.metadata["tags"] for c in out.cells[2:])
    assert nb.cells[0].source == md, "the notebook given is not changed"
    for wrong in (["5.1"], ["5.1", "5.2", "5.3"]):
        with pytest.raises(ValueError, match="display equation"):
            fj.jupyter_notebook(nb, numbers=numbers, equations=wrong, figures={}, cites=cites)
    with pytest.raises(ValueError, match="no number for 'eq-x'"):
        fj.jupyter_notebook(nb, numbers={}, equations=["5.1", "5.2"], figures={}, cites=cites)


def _eqnos(path: Path) -> list[str]:
    """The numbers of a page's display equations, in page order ("5.3" of "(5.3)")."""
    return re.findall(r'<span class="eqno">\(([^)<]*)\)', path.read_text(encoding="utf-8"))


def test_every_display_equation_is_numbered(book):
    """A teacher can cite "Eq. (5.3)": every display equation of a chapter carries its number,
    the chapter's and its place in the chapter, 1, 2, ... in page order (issue 24; numfig with
    the chapters a numbered toctree).  A page outside the chapters has plain numbers."""
    total = 0
    for chapter in CHAPTERS:
        path = book / "chapters" / f"{chapter.stem}.html"
        page = parse(path)
        shown = len(page.find("div", "math"))
        numbers = _eqnos(path)
        assert len(numbers) == shown, f"{chapter.name}: {shown - len(numbers)} equations unnumbered"
        c = int(chapter.stem[:2])
        assert numbers == [f"{c}.{k}" for k in range(1, shown + 1)], f"{chapter.name}: {numbers}"
        total += shown
    assert total > 20
    others = {p.relative_to(book).as_posix(): _eqnos(p) for p in _pages(book)
              if p.parent.name != "chapters"}
    assert others["notation.html"], "the notation page has no numbered equation"
    for name, numbers in others.items():
        assert all(n.isdigit() for n in numbers), f"{name}: {numbers}"


def test_chapters_are_the_numbered_sections_of_the_book(book):
    """Each chapter's page and its entry in the navigation carry its number, the number of its
    file ("5. Open-loop compensation ..." for 05_...), which its figures and equations take;
    the title does not repeat it ("Chapter 5 --" is Jupyter's title only).  The pages around
    the chapters are not numbered."""
    def title(path: Path) -> str:  # the page's own title, as the reader sees it
        html = path.read_text(encoding="utf-8")
        h1 = re.search(r"<h1>(.*?)</h1>", html[html.index("<article"):], re.S)
        assert h1, f"{path.name}: no title"
        return re.sub(r"<[^>]+>", "", h1.group(1)).replace("#", "").strip()

    nav = _anchor_texts(book / "index.html")
    for chapter in CHAPTERS:
        c = int(chapter.stem[:2])
        shown = title(book / "chapters" / f"{chapter.stem}.html")
        assert shown.startswith(f"{c}. ") and "Chapter" not in shown, f"{chapter.name}: {shown!r}"
        entries = [text for href, _, text in nav if href == f"chapters/{chapter.stem}.html"]
        assert entries and all(e == shown for e in entries), f"{chapter.name}: {entries}"
    for page in ("chapters/README.html", "run_it_yourself.html", "notation.html",
                 "reproduction.html"):
        assert not re.match(r"\d", title(book / page)), f"{page}: {title(book / page)!r}"


def test_every_image_resolves_to_a_file(book):
    count = 0
    for page in _pages(book):
        for img in parse(page).find("img"):
            src = img.get("src", "")
            assert src and not src.startswith("data:"), f"{page.name}: image without a file: {src[:60]!r}"
            target = (page.parent / unquote(urlsplit(src).path)).resolve()
            assert target.is_file() and target.stat().st_size > 0, f"{page.relative_to(book)}: {src} missing"
            count += 1
    assert count > 0
    # the claims page shows the figures of both pipelines' representative seeds
    assert len(parse(book / "reproduction.html").find("img")) >= 2 * 13


def test_every_chapter_figure_is_numbered_captioned_and_described(book):
    """Every image of a chapter is a figure with its number and caption ("Fig. 3 The ..."),
    and its alt text -- what a screen reader says, what shows when the image cannot load --
    is words (the caption's, ``read_chapter``), not the PNG's hash (issue 24 item 5)."""
    hashed = re.compile(r"[0-9a-f]{16}", re.I)  # myst-nb names output images by a SHA-256
    count = 0
    for chapter in CHAPTERS:
        page = parse(book / "chapters" / f"{chapter.stem}.html")
        numbers = []
        for img, figure in page.images:
            where = f"{chapter.name}: {img.get('src', '')}"
            alt = img.get("alt", "").strip()
            assert alt and not hashed.search(alt), f"{where}: alt text {alt!r}"
            caption = None if figure is None else page.captions[figure]
            assert caption is not None, f"{where}: not in a <figure> with a <figcaption>"
            number = re.match(r"\s*Fig\. (\d+)\.(\d+)\s*", caption)
            assert number, f"{where}: caption not numbered: {caption[:60]!r}"
            assert caption[number.end():].strip(" #\n"), f"{where}: caption without text"
            numbers.append(tuple(int(n) for n in number.groups()))
            count += 1
        # "Fig. 5.1", "Fig. 5.2", ...: the chapter's number, then the figure's place in it
        c = int(chapter.stem[:2])
        assert numbers == [(c, k) for k in range(1, len(numbers) + 1)], f"{chapter.name}: {numbers}"
    assert count > 20  # the chapters draw dozens of figures in fast mode too


def test_every_chapter_ran_without_an_error_output(book):
    for chapter in CHAPTERS:
        page = parse(book / "chapters" / f"{chapter.stem}.html")
        classes = {c for a in page.find("div") for c in a.get("class", "").split()}
        assert "traceback" not in classes, f"{chapter.name}: an error output in the page"
        assert "Traceback (most recent call last)" not in "".join(page.text), chapter.name
        assert page.find("div", "cell_output"), f"{chapter.name}: no output at all (not executed?)"


def test_solutions_are_collapsed_and_widgets_replaced(book):
    jupytext = pytest.importorskip("jupytext")
    solutions = 0
    for chapter in CHAPTERS:
        nb = jupytext.read(chapter, fmt="py:percent")
        tags = [c.metadata.get("tags", []) for c in nb.cells]
        page = parse(book / "chapters" / f"{chapter.stem}.html")
        cells = page.find("div", "cell")
        # a solution cell runs and sits, collapsed, inside a <details> under "Show the solution"
        n = sum("solution" in t for t in tags)
        assert len([a for a in cells if "tag_solution" in a["class"].split()]) == n, chapter.name
        assert "".join(page.text).count("Show the solution") == n, chapter.name
        solutions += n
        # a widget cell is not shown at all: the static fallback that follows it stands for it
        assert not [a for a in cells if "tag_widget" in a["class"].split()], chapter.name
        code = "\n".join(page.pres)
        for cell, t in zip(nb.cells, tags):
            if "widget" in t:
                assert cell.source.strip() not in code, f"{chapter.name}: a widget cell is shown"
    assert solutions > 0, "no chapter has a solution cell (chapter 1 shows one)"


def test_equations_are_marked_for_the_local_mathjax(book):
    page = parse(book / "chapters" / f"{CHAPTERS[0].stem}.html")
    assert page.find("span", "math") or page.find("div", "math"), "chapter 1 has no equation"
    scripts = [a.get("src", "") for a in page.find("script")]
    mathjax = [s for s in scripts if "mathjax" in s.lower()]
    assert mathjax, "no MathJax script on a page with equations"
    for src in mathjax:
        assert (book / "chapters" / urlsplit(src).path).resolve().is_file(), src


def test_nothing_is_loaded_from_another_host(book):
    for page in _pages(book):
        p = parse(page)
        loaded = [a.get("src", "") for t in ("script", "img", "iframe") for a in p.find(t)]
        loaded += [a.get("href", "") for a in p.find("link") if "stylesheet" in a.get("rel", "")
                   or a.get("rel", "") in ("preload", "modulepreload")]
        remote = [u for u in loaded if urlsplit(u).scheme in ("http", "https") or u.startswith("//")]
        assert not remote, f"{page.relative_to(book)} loads {remote[:3]}"


def test_api_reference_documents_every_package(book):
    index = parse(book / "api" / "index.html")
    links = {a.get("href", "").split("#")[0] for a in index.find("a")}
    for name in API_PAGES:
        assert f"{name}.html" in links, f"api/{name} is not linked from the API index"
        page = parse(book / "api" / f"{name}.html")
        objects = [a for a in page.find("dt") if a.get("id", "").startswith("fricctl.")]
        assert objects, f"api/{name}.html documents no object"
    design = {a.get("id") for a in parse(book / "api" / "design.html").find("dt")}
    assert {"fricctl.design.design_p", "fricctl.design.Design"} <= design


def _anchor_texts(path: Path) -> list[tuple[str, str, str]]:
    """Every ``<a>`` of a page with an ``href``: (href, class, text)."""
    out = []
    for m in re.finditer(r"<a\s([^>]*)>(.*?)</a>", path.read_text(encoding="utf-8"), re.S):
        attrs = dict(re.findall(r'([\w-]+)="([^"]*)"', m.group(1)))
        if "href" in attrs:
            out.append((unquote(attrs["href"]), attrs.get("class", ""),
                        re.sub(r"<[^>]+>", "", m.group(2)).strip()))
    return out


def test_every_citation_resolves_to_the_bibliography(book):
    """Each chapter's References cite the one bibliography (sphinxcontrib-bibtex,
    docs/references.bib): every citation links to an entry of bibliography.html, and that page
    lists the works issue 24 names (the paper, EMPS, python-control, CasADi, LuGre, the
    friction survey)."""
    bib = (book / "bibliography.html").read_text(encoding="utf-8")
    ids = set(re.findall(r'id="([^"]+)"', bib))
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", bib))
    for title in ("A new robotic drive joint friction compensation mechanism using neural networks",
                  "Data set and reference models of EMPS", "Python Control Systems Library",
                  "CasADi", "A new model for control of systems with friction",
                  "A survey of models, analysis tools and compensation methods"):
        assert title in text, f"bibliography.html lacks {title!r}"
    for chapter in CHAPTERS:
        page = book / "chapters" / f"{chapter.stem}.html"
        html = page.read_text(encoding="utf-8")
        cites = re.findall(r'<span class="bibtex-citation">\[?<a[^>]*href="([^"]+)"', html)
        assert cites, f"{chapter.name}: cites nothing"
        for href in cites:
            path, _, frag = href.partition("#")
            assert path == "../bibliography.html" and frag in ids, f"{chapter.name}: citation {href}"
        assert "](#" not in "".join(parse(page).text), f"{chapter.name}: a Markdown link left raw"


def test_cross_references_resolve_to_numbers(book):
    """The chapters' links to their equations and figures are numbered references in the book
    ("Eq. (5.3)", "Fig. 5.2"), each to an equation or a figure of that number on the page (or of
    another chapter), and no label or role is left raw (issue 24 item 5)."""
    numbers = {}  # the id of every numbered equation and figure of the chapters -> its number
    for chapter in CHAPTERS:
        html = (book / "chapters" / f"{chapter.stem}.html").read_text(encoding="utf-8")
        for m in re.finditer(r'id="(equation-[^"]+)"', html):
            eqno = re.search(r'<span class="eqno">\((\d+\.\d+)\)', html[m.end():m.end() + 600])
            if eqno:
                numbers[(chapter.stem, m.group(1))] = f"Eq. ({eqno.group(1)})"
        for m in re.finditer(r'<figure[^>]*id="([^"]+)"', html):
            n = re.search(r'<span class="caption-number">Fig\. (\d+\.\d+)', html[m.end():m.end() + 3000])
            if n:
                numbers[(chapter.stem, m.group(1))] = f"Fig. {n.group(1)}"
    refs = 0
    for chapter in CHAPTERS:
        page = book / "chapters" / f"{chapter.stem}.html"
        text = "".join(parse(page).text)
        for raw in ('<a id="eq-', "{eq}", "{numref}", "](#eq-", "](#fig-"):
            assert raw not in text, f"{chapter.name}: {raw!r} left raw"
        for href, cls, label in _anchor_texts(page):
            path, _, frag = href.partition("#")
            if "headerlink" in cls or not (frag.startswith("equation-eq-") or frag.startswith("fig-")):
                continue
            stem = Path(path).stem if path else chapter.stem
            assert (stem, frag) in numbers, f"{chapter.name}: {href} names nothing numbered"
            assert label == numbers[(stem, frag)], f"{chapter.name}: {href} reads {label!r}"
            refs += 1
    # one numbered reference per link of the sources (chapters 1-7 and 9 cite their equations
    # and figures; a link the book left as words, or dropped, is missing here)
    links = sum(len(re.findall(r"\]\(#(?:eq|fig)-[\w-]+\)", c.read_text(encoding="utf-8")))
                for c in CHAPTERS)
    assert refs == links > 0, (refs, links)


def test_every_fricctl_function_a_chapter_uses_links_to_the_api(book):
    """Before the first cell that uses a documented fricctl function or class, the page links
    to its API entry (fricctl_book.api_links); every such link resolves to an entry."""
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import fricctl_book

    jupytext = pytest.importorskip("jupytext")
    names = fricctl_book.api_names()
    documented: dict[str, set[str]] = {}
    for chapter in CHAPTERS:
        page = book / "chapters" / f"{chapter.stem}.html"
        links = {}
        for href, _, _ in _anchor_texts(page):
            path, _, frag = href.partition("#")
            if path.startswith("../api/") and frag.startswith("fricctl."):
                links[frag] = path
        used = [n for _, ns in fricctl_book.api_uses(jupytext.read(chapter, fmt="py:percent"), names)
                for n in ns]
        assert used or chapter.stem.startswith("08"), f"{chapter.name}: uses no fricctl function?"
        for name in used:
            assert name in links, f"{chapter.name}: no link to the API entry of {name}"
            api = book / "chapters" / links[name]
            if api not in documented:
                documented[api] = set(re.findall(r'<dt[^>]*id="([^"]+)"', api.read_text(encoding="utf-8")))
            assert name in documented[api], f"{chapter.name}: {links[name]}#{name} is no API entry"


def test_a_chapter_executed_beside_the_others_runs_as_myst_nb_runs_it(tmp_path):
    """The book's pool (fricctl_book.start_execution) runs each chapter in a process of its
    own (docs/_ext/fricctl_execute.py): the outputs come back in their cells, with the CPU
    time; a cell error fails with the error's name (what the book fixture and CI look for),
    the failing cell's code and its message -- as myst-nb's own execution fails the build."""
    pytest.importorskip("ipykernel", reason="the book needs: pip install -e '.[book]'")
    nbformat = pytest.importorskip("nbformat")
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import fricctl_book
    from sphinx.errors import ExtensionError

    cells = [nbformat.v4.new_code_cell("x = 6 * 7\nprint(x)"), nbformat.v4.new_markdown_cell("text"),
             nbformat.v4.new_code_cell("x + 1")]
    nb, wall, cpu = fricctl_book._execute_chapter("ok", nbformat.v4.new_notebook(cells=cells),
                                                  tmp_path, 600, "-")
    assert [c.cell_type for c in nb.cells] == ["code", "markdown", "code"]
    assert nb.cells[0].outputs[0]["text"] == "42\n"
    assert nb.cells[2].outputs[0]["data"]["text/plain"] == "43"
    assert wall > 0 and cpu is not None and cpu > 0  # the runner's own Python at least
    bad = [nbformat.v4.new_code_cell("y = 1"), nbformat.v4.new_code_cell("assert y == 2, 'y is not 2'")]
    with pytest.raises(ExtensionError, match="(?s)CellExecutionError.*assert y == 2.*y is not 2"):
        fricctl_book._execute_chapter("bad", nbformat.v4.new_notebook(cells=bad), tmp_path, 600, "-")


def test_the_pool_runs_its_processes_with_one_blas_thread_unless_told(monkeypatch):
    """Each process of the book's pool (chapters, reproduce) gets OPENBLAS/OMP/MKL_NUM_THREADS=1,
    so BLAS's own threads do not oversubscribe the CPUs the pool already fills; a value the
    environment sets is kept."""
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import fricctl_book

    show = [sys.executable, "-c", "import os; print([os.environ.get(k) for k in "
            "('OPENBLAS_NUM_THREADS', 'OMP_NUM_THREADS', 'MKL_NUM_THREADS')])"]
    monkeypatch.delenv("OPENBLAS_NUM_THREADS", raising=False)
    assert fricctl_book._run(show, what="test").stdout.strip() == "['1', '1', '1']"
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "2")
    assert fricctl_book._run(show, what="test").stdout.strip().startswith("['2', ")
    assert fricctl_book._run(show, what="test", env={"PATH": os.environ.get("PATH", "")}
                             ).stdout.strip() == "['1', '1', '1']"


def test_claims_details_are_folded_after_the_summary_table(book):
    """The claims page: the at-a-glance table first, then each detail section collapsed in a
    ``<details>`` under its title, none opened, none cutting a section (issue 24 item 3)."""
    html = (book / "reproduction.html").read_text(encoding="utf-8")
    folds = [m.start() for m in re.finditer(r'<details class="fricctl-details"', html)]
    assert len(folds) >= 4, f"{len(folds)} folded sections"
    glance = html.find('<section id="at-a-glance">')  # the section, not the page's contents
    assert 0 <= glance < html.find("<table", glance) < folds[0], "the summary table is not first"
    for start in folds:
        end = html.find("</details>", start)
        block = html[start:end]
        assert "<summary>" in block and " open" not in block[:60], block[:120]
        assert "<section" not in block and "</section>" not in block, "a fold cuts a section"


def test_the_claims_page_shows_every_bench_side_by_side(book):
    """The summary table of the claims page has a column per bench and pipeline (issue 22),
    each cell what that bench's own ``fricctl reproduce --bench NAME`` wrote in its
    ``claims.json`` (beside the book: ``reproduce/``, ``reproduce-<bench>/``), not typed."""
    import json

    from fricctl.paper.benches import BENCHES, DEFAULT_BENCH

    html = (book / "reproduction.html").read_text(encoding="utf-8")
    glance = html.find('<section id="at-a-glance">')
    assert glance >= 0, "no section At a glance"
    table = html[html.find("<table", glance):html.find("</table>", glance)]
    head = [re.sub(r"<[^>]+>", "", h).strip() for h in re.findall(r"<th[^>]*>(.*?)</th>", table, re.S)]
    rows = [[re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", r, re.S)]
            for r in re.findall(r"<tr[^>]*>(.*?)</tr>", table, re.S)]
    rows = {r[0].removesuffix(" (extra)"): r for r in rows if r}
    checked = 0
    for bench in BENCHES:
        folder = book.parent / ("reproduce" if bench == DEFAULT_BENCH else f"reproduce-{bench}")
        claims = json.loads((folder / "claims.json").read_text(encoding="utf-8"))
        for c in claims:
            assert c["bench"] == bench
            column = head.index(f"{bench} bench, {c['pipeline']} pipeline")
            verdict = "reproduced" if c["passed"] else "not reproduced"
            assert rows[c["id"]][column].startswith(f"{verdict}, {c['n_passed']} of {c['n_seeds']}"), (
                bench, c["id"], rows[c["id"]][column])
            checked += 1
    assert checked >= 2 * len(BENCHES) * 16, checked


# -- the PDF ---------------------------------------------------------------------------------

def test_the_pdf_holds_the_whole_book(book, tmp_path):
    """``make book-pdf``: Sphinx's LaTeX builder on the notebooks the HTML build executed, and
    latexmk with XeLaTeX -- the PDF exists, has the pages of a book, and its text holds every
    chapter's title (pdftotext).  ``FRICCTL_BOOK_PDF`` names a PDF already built by
    ``make book-pdf`` (CI); otherwise it is built here from the HTML book."""
    need = [t for t in ("latexmk", "xelatex", "pdftotext", "pdfinfo") if shutil.which(t) is None]
    if need:
        pytest.skip(f"no LaTeX: {', '.join(need)} missing (Debian: texlive-latex-recommended "
                    "texlive-latex-extra texlive-fonts-recommended texlive-xetex latexmk "
                    "fonts-freefont-otf poppler-utils; `make book-pdf` installs them as root)")
    given = os.environ.get("FRICCTL_BOOK_PDF")
    if given:
        pdf = Path(given)
    else:
        out = tmp_path / "latex"
        cmd = [sys.executable, "-m", "sphinx", "-b", "latex", "-E", "-W", "--keep-going", "-T",
               "-d", str(tmp_path / "doctrees"), "-D", "nb_execution_mode=off",
               "-D", f"fricctl_executed_notebooks={book / '_sources' / 'chapters'}",
               "-D", "fricctl_reproduce=reuse",
               "-D", f"fricctl_reproduce_dir={book.parent / 'reproduce'}",
               str(ROOT / "docs"), str(out)]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
        proc = subprocess.run(["make", "-C", str(out), "LATEXMKOPTS=-silent -interaction=nonstopmode",
                               "all-pdf"], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stdout[-5000:] + proc.stderr[-3000:]
        pdf = out / "fricctl.pdf"
    assert pdf.is_file() and pdf.stat().st_size > 0, f"no {pdf}"
    info = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, check=True).stdout
    pages = int(re.search(r"^Pages:\s+(\d+)", info, re.M).group(1))
    assert pages > 150, f"{pages} pages"  # nine chapters with figures, the claims, the API
    text = subprocess.run(["pdftotext", "-enc", "UTF-8", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    flat = re.sub(r"\s+", " ", text)
    jupytext = pytest.importorskip("jupytext")
    for chapter in CHAPTERS:
        nb = jupytext.read(chapter, fmt="py:percent")
        title = next(c.source for c in nb.cells if c.cell_type == "markdown").splitlines()[0]
        # the words after "Chapter N --" (Sphinx types the dash as an en dash)
        title = re.split(r"\s(?:--|\u2014|\u2013)\s", title.lstrip("# ").replace("`", ""))[-1].strip()
        assert title in flat, f"the PDF lacks the title of {chapter.name}: {title!r}"
        # numbered as the HTML (fricctl_book.latex_numbering): every figure of the chapter's page
        # under its number ("Fig. 5.2: ..." in LaTeX), every equation it cites as the page does
        html = (book / "chapters" / f"{chapter.stem}.html").read_text(encoding="utf-8")
        for number in re.findall(r'<span class="caption-number">Fig\. (\d+\.\d+)', html):
            assert f"Fig. {number}:" in flat, f"the PDF has no Fig. {number} ({chapter.name})"
        for ref in set(re.findall(r"Eq\. \(\d+\.\d+\)", re.sub(r"<[^>]+>", "", html))):
            assert ref in flat, f"the PDF does not cite {ref} ({chapter.name})"


# -- in a browser ----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def browser():
    if not (CHROMIUM.is_file() and CHROMEDRIVER.is_file()):
        pytest.skip(f"no headless browser: {CHROMIUM} and {CHROMEDRIVER} come from Debian's "
                    "chromium and chromium-driver packages")
    webdriver = pytest.importorskip("selenium.webdriver", reason="pip install -e '.[book]'")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--no-first-run", "--window-size=1280,1024"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)
    # generous: a loaded machine may take long to lay out a page of figures, never this long
    driver.set_script_timeout(300)
    driver.set_page_load_timeout(300)
    yield driver
    driver.quit()


_LOAD = """
const done = arguments[arguments.length - 1];
(async () => {
  for (const img of document.images) {            // decode every image, lazy or not
    img.loading = "eager";
    img.scrollIntoView();
    try { await img.decode(); } catch (e) {}
  }
  if (document.querySelector(".math") && window.MathJax && MathJax.startup) {
    await MathJax.startup.promise;
  }
  const math = [...document.querySelectorAll("span.math, div.math")];
  done({
    images: [...document.images].map(i => [i.getAttribute("src"), i.naturalWidth]),
    math: math.length,
    typeset: math.filter(m => m.querySelector("mjx-container")).length,
    errors: document.querySelectorAll("mjx-merror").length,
    mathjax: !!(window.MathJax && MathJax.startup),
    resources: performance.getEntriesByType("resource").map(r => r.name),
    solutions: [...document.querySelectorAll("div.tag_solution details")].map(d => d.open),
  });
})();
"""


def _browse(browser, page: Path) -> dict:
    browser.get(page.as_uri())
    return browser.execute_async_script(_LOAD)


def test_pages_render_in_a_browser(book, browser):
    # the index, two chapters with equations and figures, and the claims with their figures
    pages = [book / "index.html", book / "chapters" / f"{CHAPTERS[0].stem}.html",
             book / "chapters" / "08_when_the_model_is_wrong.html", book / "reproduction.html"]
    for page in pages:
        name = page.relative_to(book).as_posix()
        r = _browse(browser, page)
        broken = [src for src, width in r["images"] if not width > 0]
        assert not broken, f"{name}: images that did not load: {broken}"
        remote = [u for u in r["resources"] if not u.startswith("file:")]
        assert not remote, f"{name}: fetched from the network: {remote[:3]}"
        if name.startswith("chapters/"):
            assert r["images"], f"{name}: no figure"
            assert r["math"] > 0, f"{name}: no equation"
        if r["math"]:
            assert r["mathjax"], f"{name}: MathJax did not start"
            assert r["typeset"] == r["math"], f"{name}: {r['math'] - r['typeset']} equations not typeset"
            assert r["errors"] == 0, f"{name}: {r['errors']} TeX errors"
        assert not any(r["solutions"]), f"{name}: a solution is open"
    assert _browse(browser, pages[1])["solutions"], "chapter 1 shows no collapsed solution"


def test_printing_opens_the_solutions_and_figures_zoom(book, browser):
    """Paper holds the solutions (fricctl.js opens every collapsed block before printing and
    closes it after); a chapter's figure opens at full size when clicked."""
    browser.get((book / "chapters" / f"{CHAPTERS[0].stem}.html").as_uri())
    opened = browser.execute_script("""
        const closed = () => [...document.querySelectorAll("details")].filter(d => !d.open).length;
        const before = closed();
        window.dispatchEvent(new Event("beforeprint"));
        const during = closed();
        window.dispatchEvent(new Event("afterprint"));
        return [before, during, closed(),
                document.querySelectorAll("div.cell_output img.fricctl-zoom").length];
    """)
    before, during, after, zoom = opened
    assert before > 0 and during == 0 and after == before, opened
    assert zoom > 0, "no figure of chapter 1 opens at full size"


def test_the_pdf_reuses_a_notebook_only_if_executed_with_the_same_fricctl(tmp_path, monkeypatch):
    """``make book-pdf`` takes each chapter's outputs from the notebook the HTML build executed
    (fricctl_book.read_chapter) only when that build ran the same chapter code *and* the same
    fricctl: the notebook records the digest of the package (its sources and data files, not
    bytecode), and one executed with another -- or with none recorded -- is refused."""
    nbformat = pytest.importorskip("nbformat")
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import fricctl_book
    from sphinx.errors import ExtensionError

    # the digest follows every source and data file of a package, and nothing else
    pkg = tmp_path / "pkg"
    (pkg / "bench").mkdir(parents=True)
    (pkg / "a.py").write_text("x = 1\n")
    (pkg / "bench" / "literal.json").write_text('{"k": 1}\n')
    first = fricctl_book.package_digest(pkg)
    (pkg / "__pycache__").mkdir()
    (pkg / "__pycache__" / "a.cpython-311.pyc").write_bytes(b"\0\1")
    assert fricctl_book.package_digest(pkg) == first
    (pkg / "bench" / "literal.json").write_text('{"k": 2}\n')
    second = fricctl_book.package_digest(pkg)
    (pkg / "a.py").write_text("x = 2\n")
    assert len({first, second, fricctl_book.package_digest(pkg)}) == 3

    # a notebook "executed" by this build (its digest recorded when it was read) is reused ...
    text = "# %% [markdown]\n# # Chapter 1 -- A test\n\n# %%\nprint(6 * 7)\n"
    nb = fricctl_book._read_chapter(text)
    nb.cells[1].outputs = [nbformat.v4.new_output("stream", name="stdout", text="42\n")]
    executed = tmp_path / "01_test.ipynb"
    nbformat.write(nb, executed)
    monkeypatch.setitem(fricctl_book.EXECUTED, text, executed)
    assert fricctl_book.read_chapter(text).cells[1].outputs[0]["text"] == "42\n"
    # ... not once the package it ran differs from the package now
    monkeypatch.setattr(fricctl_book, "_package_digest", lambda: "another fricctl")
    with pytest.raises(ExtensionError, match="other fricctl sources"):
        fricctl_book.read_chapter(text)
    monkeypatch.undo()
    # ... nor when it records none (executed before the digest was kept)
    del nb.metadata[fricctl_book.DIGEST_KEY]
    nbformat.write(nb, executed)
    monkeypatch.setitem(fricctl_book.EXECUTED, text, executed)
    with pytest.raises(ExtensionError, match="other fricctl sources"):
        fricctl_book.read_chapter(text)
