"""The cells of the report's page (report_html): escaping, the number formats every table and
caption uses, and table rows. A value that is missing or not a finite number shows as "–".
"""

import html
import math


def escape(text):
    return html.escape(str(text))


def number(value, spec):
    if value is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        return "–"
    if isinstance(value, float) and not math.isfinite(value):
        return "–"
    return format(value, spec)


def mm(value):
    return number(value, ".3f")


def mm2(value):
    return number(value, ".4f")


def ratio(value):
    return number(value, ".2f")


def statistic(value):
    return number(value, ".4g")


def p_value(value):
    return number(value, ".3g")


def row(cells, cls=None):
    attribute = f' class="{cls}"' if cls else ""
    return f"<tr{attribute}>" + "".join(cells) + "</tr>"


def td(text, cls=None):
    return f'<td class="{cls}">{escape(text)}</td>' if cls else f"<td>{escape(text)}</td>"


def figure_html(anchor, cls, figure, head):
    """A figure with its caption: `head` (HTML) first, then the figure's own caption."""
    return (f'<figure id="{escape(anchor)}" class="{cls}"><img src="{escape(figure.file)}" '
            f'alt="{escape(figure.paper)}"><figcaption>{head} {escape(figure.caption)}'
            f"</figcaption></figure>")
