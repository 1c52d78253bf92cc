"""The receivers' output of the Green's-function soil: its rows of
receiver velocities per step as (x, y, z) components, and vibration.csv
with the horizontal levels (the participant and the study write the same
files)."""
import numpy as np

from fe_soil import measures


def vertical_up(rows):
    """The soil's vertical rows (along the force: down) as the files give
    them: z up, as the FE soil's."""
    return -np.asarray(rows, dtype=float)


def components(series, n):
    """(steps, n, 3) velocities (x, y, z; z up) from the soil's receiver rows
    per step (the n vertical ones, down, then x, then y; only the vertical
    ones when the soil has no horizontal rows)."""
    series = np.asarray(series, dtype=float).reshape(len(series), -1)
    v = np.zeros((len(series), n, 3))
    v[:, :, 2] = vertical_up(series[:, :n])
    if series.shape[1] >= 3 * n:
        v[:, :, 0] = series[:, n:2 * n]
        v[:, :, 1] = series[:, 2 * n:3 * n]
    return v


def vibration_csv(names, xs, ys, summaries, bands):
    """The FE soil's vibration.csv (fe_soil.measures) with the horizontal
    one-third-octave levels after its columns: Lv_x_<f>Hz_dB (along the
    rail), then Lv_y_<f>Hz_dB (across), per band; then the resolved bands
    (measures.with_resolved; bands: resolution.receiver_bands)."""
    lines = measures.vibration_csv(names, xs, ys, summaries).split("\n")
    centres = summaries[0]["band_centres"] if summaries else []
    lines[0] += "".join(",Lv_%s_%gHz_dB" % (c, f) for c in "xy" for f in centres)
    for k, r in enumerate(summaries):
        lines[k + 1] += "".join(",%.9g" % v for v in r["band_levels"][0] + r["band_levels"][1])
    return measures.with_resolved("\n".join(lines), bands)
