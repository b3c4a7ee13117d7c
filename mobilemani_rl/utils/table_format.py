"""Result tables rendered as Markdown and LaTeX (booktabs), laid out like the paper's."""

from __future__ import annotations

from dataclasses import dataclass


def pct(value: float | None) -> str:
    """A success rate in [0, 1] as a percentage with one decimal, '-' where there is none."""
    return "-" if value is None else f"{100.0 * value:.1f}"


def num(value: float | None) -> str:
    """A number already in percent (the paper's) with one decimal, '-' where there is none."""
    return "-" if value is None else f"{value:.1f}"


@dataclass
class Table:
    header: list[str]
    rows: list[list[str]]
    caption: str = ""
    separators: tuple[int, ...] = ()  # row indices before which a horizontal rule goes

    def markdown(self) -> str:
        lines = [f"| {' | '.join(self.header)} |", "|" + "|".join("---" for _ in self.header) + "|"]
        lines += [f"| {' | '.join(row)} |" for row in self.rows]
        return (f"**{self.caption}**\n\n" if self.caption else "") + "\n".join(lines) + "\n"

    def latex(self) -> str:
        escape = str.maketrans({"%": r"\%", "_": r"\_", "&": r"\&", "#": r"\#"})
        columns = "l|" + "c" * (len(self.header) - 1)
        body = []
        for i, row in enumerate(self.rows):
            if i in self.separators:
                body.append(r"\midrule")
            body.append(" & ".join(cell.translate(escape) for cell in row) + r" \\")
        return "\n".join(
            [
                r"\begin{table}[t]",
                r"\centering",
                rf"\begin{{tabular}}{{{columns}}}",
                r"\toprule",
                " & ".join(h.translate(escape) for h in self.header) + r" \\",
                r"\midrule",
                *body,
                r"\bottomrule",
                r"\end{tabular}",
                rf"\caption{{{self.caption.translate(escape)}}}",
                r"\end{table}",
                "",
            ]
        )
