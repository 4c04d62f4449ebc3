"""Batch runs from the command line (`python3 -m freecad_deform`): run, sweep and solve.

One module per subcommand (run, sweep, solve), the document helpers they share (model) and
finding FreeCAD (env). The geometry layer is not involved: everything here drives
documents through their properties, as a user would.
"""
