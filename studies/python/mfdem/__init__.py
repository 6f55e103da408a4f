"""Reading and drawing mfdem's outputs: the one Python side of the project.

The numbers are computed by the C++ (`mfdem`); this package only reads what it wrote and draws it.
    files            the readers of packing.h5, push.h5, a run store and compare's outputs
    tables           Markdown tables
    figures          figure helpers (saving PNG and SVG, model colours, the sleeper outline)
    compare_figures  the four figures of `mfdem compare` (python3 -m mfdem.compare_figures OUT)
Needs h5py, numpy and matplotlib from Debian (python3-h5py, python3-matplotlib): run it with
/usr/bin/python3 and studies/python on PYTHONPATH (the scripts in studies/railway set it).
"""
