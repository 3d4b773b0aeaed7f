"""``dynlab serve``: a local web page for the labs — a form per lab generated from its spec,
the same boundary, reduction and reports as ``dynlab run``, and a teacher's class page."""
