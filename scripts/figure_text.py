"""Text that stays readable in the study's figures (figures.py,
speed_accuracy.py): titles wrapped to the canvas, a legend given as many
columns as fit, and labels placed beside their points without covering one
another. tests/figure_layout_test.py checks the result on 4 and 12 methods.
"""
import textwrap

# A character of the default sans-serif font is about this many ems wide
# (measured on the figures' texts: 0.50-0.56); a little more keeps a margin.
EM_PER_CHAR = 0.6


def wrapped(text, width_in, fontsize):
    """`text` broken into lines no wider than width_in inches at fontsize
    points (its own line breaks kept)."""
    chars = max(20, int(width_in * 72 / (fontsize * EM_PER_CHAR)))
    return "\n".join(textwrap.fill(line, chars) for line in text.split("\n"))


def title_height(text, fontsize):
    """Inches a title of these lines takes, with its spacing."""
    return (text.count("\n") + 1) * fontsize * 1.25 / 72 + 0.05


def fit_legend(fig, most_columns, **kw):
    """fig.legend(**kw) with the most columns up to most_columns whose width
    fits the canvas; returns the legend and its height in inches."""
    r = fig.canvas.get_renderer()
    for ncol in range(most_columns, 0, -1):
        g = fig.legend(ncol=ncol, **kw)
        e = g.get_window_extent(r)
        if e.width <= 0.98 * fig.bbox.width or ncol == 1:
            return g, e.height / fig.dpi
        g.remove()
    raise AssertionError("unreachable")


def place_labels(fig, labels, pad=1.0):
    """Annotates each (ax, text, x, y, kwargs) beside its point (x, y) in
    data coordinates: to its upper right if free, else the nearest free
    place above or below, or to its left, inside the axes and not over a
    label placed before it. Labels are placed from the top of each axes
    down, in display coordinates measured with the canvas's renderer."""
    r = fig.canvas.get_renderer()
    placed = {}
    order = sorted(labels, key=lambda l: -l[0].transData.transform((l[2], l[3]))[1])
    for ax, text, x, y, kw in order:
        taken = placed.setdefault(ax, [])
        box = ax.bbox
        height = None
        best = None
        for k in range(0, 40):
            step = (k + 1) // 2 * (1 if k % 2 else -1)  # 0, +1, -1, +2, -2, ...
            for dx, ha in ((4, "left"), (-4, "right")):
                dy = 2 + step * (height or 0)
                a = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", ha=ha,
                                annotation_clip=False, **kw)
                e = a.get_window_extent(r)
                if height is None:
                    height = e.height * 72 / fig.dpi + pad
                inside = e.x0 >= box.x0 and e.x1 <= box.x1 and e.y0 >= box.y0 and e.y1 <= box.y1
                if inside and not any(e.overlaps(t) for t in taken):
                    best = (a, e)
                    break
                a.remove()
            if best or height == 0:
                break
        if best is None:  # nowhere free: at the point, as before
            a = ax.annotate(text, (x, y), xytext=(4, 2), textcoords="offset points", **kw)
            best = (a, a.get_window_extent(r))
        taken.append(best[1])
