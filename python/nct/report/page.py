"""One self-contained HTML page: its style and script inline, its figures
inline SVG, no network, readable from the file.

    page = Page("run default", "a puff run")
    s = page.section("biomarkers", "Biomarkers")
    s.table(["name", "value"], [["DA", "1.09 mm"]])
    s.figure(fig, "the apex curve")          # a matplotlib figure, inline SVG
    page.write(path)                         # atomically: path.tmp, then renamed
"""
import html
import json
import os
import pathlib

from ..figures import svg

HERE = pathlib.Path(__file__).parent


def escape(text):
    return html.escape(str(text), quote=True)


class Section:
    """A <section> of the page: paragraphs, tables, figures, raw HTML."""

    def __init__(self, ident, title):
        self.ident, self.title, self.parts = ident, title, []

    def paragraph(self, text, css=None):
        """A paragraph of plain text (escaped)."""
        cls = f' class="{css}"' if css else ""
        self.parts.append(f"<p{cls}>{escape(text)}</p>")

    def raw(self, markup):
        """HTML as it is (the caller escapes)."""
        self.parts.append(markup)

    def table(self, head, rows, css="", flags=None, caption=None):
        """A table of text cells; rows whose index is in flags are marked."""
        flags = flags or set()
        out = [f'<table class="{css}">']
        if caption:
            out.append(f"<caption>{escape(caption)}</caption>")
        out.append("<thead><tr>" + "".join(f"<th>{escape(h)}</th>" for h in head)
                   + "</tr></thead><tbody>")
        for i, row in enumerate(rows):
            mark = ' class="flag"' if i in flags else ""
            out.append(f"<tr{mark}>" + "".join(f"<td>{escape(c)}</td>" for c in row) + "</tr>")
        out.append("</tbody></table>")
        self.parts.append("".join(out))

    def figure(self, fig, caption, name=""):
        """A matplotlib figure as inline SVG with its caption (closes fig)."""
        self.parts.append(f'<figure class="plot" data-name="{escape(name)}">{svg(fig)}'
                          f"<figcaption>{escape(caption)}</figcaption></figure>")

    def html(self):
        return (f'<section id="{escape(self.ident)}"><h2>{escape(self.title)}</h2>'
                + "\n".join(self.parts) + "</section>")


class Page:
    """A report page: a title, a subtitle, sections in order, data for its
    script (JSON in a <script type="application/json"> element)."""

    def __init__(self, kind, title, subtitle=""):
        self.kind, self.title, self.subtitle = kind, title, subtitle
        self.sections, self.data, self.scripts = [], {}, []

    def section(self, ident, title):
        s = Section(ident, title)
        self.sections.append(s)
        return s

    def script(self, name):
        """Inline one of this package's scripts (name.js)."""
        self.scripts.append((HERE / f"{name}.js").read_text())

    def html(self):
        nav = " ".join(f'<a href="#{escape(s.ident)}">{escape(s.title)}</a>'
                       for s in self.sections)
        data = json.dumps(self.data, separators=(",", ":")).replace("</", "<\\/")
        return "\n".join([
            "<!DOCTYPE html>",
            '<html lang="en"><head><meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>{escape(self.title)}</title>",
            f"<style>{(HERE / 'report.css').read_text()}</style></head>",
            f'<body class="report-{escape(self.kind)}"><header><h1>{escape(self.title)}</h1>'
            f'<p class="subtitle">{escape(self.subtitle)}</p><nav>{nav}</nav></header><main>',
            *[s.html() for s in self.sections],
            "</main><footer>Written by nct report. Everything on this page is in this one "
            "file.</footer>",
            f'<script type="application/json" id="report-data">{data}</script>',
            *[f"<script>{js}</script>" for js in self.scripts],
            "</body></html>"])

    def write(self, path):
        """The page to path, whole or not at all (a temporary file renamed)."""
        path = pathlib.Path(path)
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(self.html())
        os.replace(tmp, path)
        return path


def link(target, text=None):
    """An <a> to a path relative to the page (escaped)."""
    return f'<a href="{escape(target)}">{escape(text or target)}</a>'


def links(folder, names):
    """Links to those of the named files the folder holds, comma separated."""
    folder = pathlib.Path(folder)
    return ", ".join(link(n) for n in names if (folder / n).is_file())


def number(value, digits=4, sign=""):
    """A value as text: '-' for None or NaN."""
    if value is None or (isinstance(value, float) and value != value):
        return "-"
    return f"{value:{sign}.{digits}g}"
