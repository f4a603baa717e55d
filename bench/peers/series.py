"""The series bench/peers/peri_series prints and the re-implementations print: one line per
step, `step mean_damage mean_broken_fraction kinetic_energy strain_energy` (other lines ignored)."""


def rows(text):
    """{step: [four values]} of the series lines in text."""
    out = {}
    for line in text.splitlines():
        f = line.split()
        if len(f) == 5:
            out[int(f[0])] = [float(v) for v in f[1:]]
    return out
