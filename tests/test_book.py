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


def test_every_display_equation_is_numbered(book):
    """A teacher can cite "Chapter 5, Eq. (3)": every display equation of a chapter carries
    its number (issue 24), numbered from 1 on each page."""
    total = 0
    for chapter in CHAPTERS:
        page = parse(book / "chapters" / f"{chapter.stem}.html")
        shown = len(page.find("div", "math"))
        numbers = page.find("span", "eqno")
        assert len(numbers) == shown, f"{chapter.name}: {shown - len(numbers)} equations unnumbered"
        total += shown
    assert total > 20


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
        for img, figure in page.images:
            where = f"{chapter.name}: {img.get('src', '')}"
            alt = img.get("alt", "").strip()
            assert alt and not hashed.search(alt), f"{where}: alt text {alt!r}"
            caption = None if figure is None else page.captions[figure]
            assert caption is not None, f"{where}: not in a <figure> with a <figcaption>"
            number = re.match(r"\s*Fig\. \d+\s*", caption)
            assert number, f"{where}: caption not numbered: {caption[:60]!r}"
            assert caption[number.end():].strip(" #\n"), f"{where}: caption without text"
            count += 1
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
