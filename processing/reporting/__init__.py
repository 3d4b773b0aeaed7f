"""Reports: a result laid out as HTML and an A4 PDF, in English or Russian, with figures."""
