"""Output: LaTeX, the derivations, the paper's formulas, evaluation, JSON and files.

- :mod:`~kbm.output.latex`: LaTeX in the paper's notation (:func:`kbm.latex`);
- :mod:`~kbm.output.derivations`: the files of ``derivations/``, with the errata section of
  :mod:`~kbm.output.errata_tex`; :mod:`~kbm.output.paper`: the paper's second-order formulas
  as printed, and their errata;
- :mod:`~kbm.output.evaluate`: numpy and mpmath functions of KBM expressions;
- :mod:`~kbm.output.strict_json`: the one JSON layer of results;
  :mod:`~kbm.output.files`: output folders and files.
"""
