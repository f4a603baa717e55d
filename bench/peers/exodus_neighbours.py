#!/usr/bin/env python3
"""Sums a per-node variable (default Number_Of_Neighbors) over Peridigm's Exodus II output
files (one per rank: NAME.e, or NAME.e.R.r) at the first time step and prints the sum: the
directed bonds of the run. python3-netcdf4.

  exodus_neighbours.py FILE... [--variable Number_Of_Neighbors]
"""
import sys

import netCDF4


def names(ds, var):
    if var not in ds.variables:
        return []
    return ["".join(c.decode() for c in row if c not in (b"", b"\x00")).strip() for row in ds.variables[var][:]]


def first_step_sum(path, variable):
    with netCDF4.Dataset(path) as ds:
        ds.set_auto_mask(False)
        nodal = names(ds, "name_nod_var")
        if variable in nodal:
            k = nodal.index(variable) + 1
            values = ds.variables["vals_nod_var%d" % k][0] if "vals_nod_var%d" % k in ds.variables \
                else ds.variables["vals_nod_var"][0, k - 1]
            return float(values.sum())
        element = names(ds, "name_elem_var")
        if variable in element:
            k = element.index(variable) + 1
            total, block = 0.0, 1
            while "vals_elem_var%deb%d" % (k, block) in ds.variables:
                total += float(ds.variables["vals_elem_var%deb%d" % (k, block)][0].sum())
                block += 1
            return total
    raise SystemExit("exodus_neighbours: %s: no variable %s" % (path, variable))


def main():
    args = sys.argv[1:]
    variable = "Number_Of_Neighbors"
    if "--variable" in args:
        i = args.index("--variable")
        variable = args[i + 1]
        del args[i:i + 2]
    if not args:
        raise SystemExit(__doc__)
    print("%.0f" % sum(first_step_sum(path, variable) for path in args))


if __name__ == "__main__":
    main()
