"""Tables as text: Markdown for the case pages, aligned columns for the
terminal.

    print(markdown.table(["case", "wall [s]"], [["l3", "23.0"], ["l4", "107.0"]]))
"""


def table(head, rows):
    """A Markdown table; every cell is printed as str()."""
    lines = ["| " + " | ".join(map(str, head)) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(map(str, r)) + " |" for r in rows]
    return "\n".join(lines)


def aligned(head, rows):
    """Right-aligned columns, two spaces apart."""
    cells = [list(map(str, head))] + [list(map(str, r)) for r in rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(head))]
    return "\n".join("  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in cells)
