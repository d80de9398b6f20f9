"""Symbolic models of Zhu, Song, Lim & Peng (MMT 59, 2013), one module per part of the paper.

Only this package and the code generator import sympy; the runtime (``beveloid``) uses
the numeric modules that ``beveloid derive`` writes into ``generated/``.

    eq01_03_rack_cutter        Eqs 1-3   rack cutter (tilted, helical, profile-shifted)
    eq04_07_tooth_surface      Eqs 4-7   generating motion, envelope / meshing equation
    eq08_17_pitch_cones        Eqs 8-17  pitch cones, tangency, helix matching, offset
    eq18_21_line_contact       Eqs 18-21 contact lines with the common rack, FPD angles
    eq22_27_working_data       Eqs 22-27 reference vs working data, backlash-free condition
    eq28_38_meshing_model      Eqs 28-38 assembly with the five errors, TCA system
    paper                      the printed forms, typed from equations.md, kept apart
"""
