"""The table rows of a study's REPORT.md, for the soils' study tests
(tests/fe_soil, tests/green_soil)."""


def report_rows(report, heading):
    """The table rows (cells) of a REPORT.md under the first line starting
    with heading, up to the next heading; header and separator left out."""
    lines = report.splitlines()
    start = next(i for i, x in enumerate(lines) if x.startswith(heading))
    rows = []
    for x in lines[start + 1:]:
        if x.startswith("#"):
            break
        if x.startswith("|"):
            rows.append([c.strip() for c in x.strip().strip("|").split("|")])
    return rows[2:]
