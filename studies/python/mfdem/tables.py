"""Markdown tables for terminals and results pages."""


def markdown_table(header, rows, align=None) -> str:
    """A Markdown table; align is a string of 'l'/'r' per column (default: first left, rest right).

    Cells are str()-ed as given: format numbers before passing them.
    """
    align = align or "l" + "r" * (len(header) - 1)
    rows = [[str(c) for c in r] for r in rows]
    widths = [max(len(str(h)), *(len(r[k]) for r in rows)) if rows else len(str(h)) for k, h in enumerate(header)]

    def line(cells):
        return "| " + " | ".join(c.ljust(w) if a == "l" else c.rjust(w)
                                 for c, w, a in zip(cells, widths, align)) + " |"
    rule = "|" + "|".join(("-" * (w + 1) + ":") if a == "r" else ("-" * (w + 2)) for w, a in zip(widths, align)) + "|"
    return "\n".join([line([str(h) for h in header]), rule] + [line(r) for r in rows])


def print_table(header, rows, align=None) -> None:
    print(markdown_table(header, rows, align))
