"""Edits a copy of a peri checkpoint the way a damaged or crafted file would be, for
tests/cli/checkpoint_input.sh. Needs h5py (Debian python3-h5py).

  craft_checkpoint.py SRC DST attr PATH NAME VALUE     an integer attribute set to VALUE
  craft_checkpoint.py SRC DST attr_array PATH NAME N   an attribute replaced by N values
  craft_checkpoint.py SRC DST rank3 DATASET            a dataset replaced by one of 5 dimensions
  craft_checkpoint.py SRC DST chunk DATASET MASK N     its first chunk stored as N bytes with
                                                       filter mask MASK (1: checksum skipped)
"""
import shutil
import sys

import h5py
import numpy as np

src, dst, what = sys.argv[1:4]
shutil.copy(src, dst)
with h5py.File(dst, "r+") as f:
    if what == "attr":
        path, name, value = sys.argv[4:7]
        old = f[path].attrs[name]
        f[path].attrs.modify(name, np.array(int(value), dtype=old.dtype))
    elif what == "attr_array":
        path, name, n = sys.argv[4:7]
        dtype = f[path].attrs[name].dtype
        del f[path].attrs[name]
        f[path].attrs.create(name, np.zeros(int(n), dtype=dtype))
    elif what == "rank3":
        path = sys.argv[4]
        del f[path]
        f.create_dataset(path, data=np.zeros((4, 4, 4, 4, 4)))
    elif what == "chunk":
        path, mask, n = sys.argv[4:7]
        f[path].id.write_direct_chunk((0,) * f[path].ndim, bytes(int(n)), filter_mask=int(mask))
    else:
        sys.exit("unknown edit " + what)
