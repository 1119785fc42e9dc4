"""The paper's cases: the parameter studies of Figs. 6-9 (Cho & Cha 2010),
the horizons and output density of the reproduction, the figure names."""

#: the paper's parameter studies: (figure, parameter, values, legend label, t_end)
VELOCITIES = [1.87, 2.73, 4.23, 5.50]
SEAL_C = [2.556e3, 2.556e4, 2.556e5, 2.556e6]
OIL_K = [0.922e8, 2.228e8, 5.228e8, 8.228e8]
V_TABLE1 = 2.73

#: simulation horizon for the table: long enough for the slowest pulse
#: (c2 = 2.556e6 N s/m lasts about 57 ms) to end
T_TABLE = 0.12
N_PER_MS = 200   # output points per ms (5 us apart)

FIGURES = ("fig4_contact_force", "fig5_pressure", "fig6_pressure_velocity",
           "fig7_displacement_velocity", "fig8_pressure_seal_friction",
           "fig9_pressure_oil_stiffness", "split_piston_force_front", "damping_laws",
           "drop_blows")

STYLES = [dict(color="k", ls="-"), dict(color="tab:red", ls="--"),
          dict(color="tab:blue", ls="-."), dict(color="tab:green", ls=":")]
