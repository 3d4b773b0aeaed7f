"""The ``dynlab`` command line: its parser, the synth options, the docs' gallery."""
