"""What the paper states in numbers (Bartels et al., "The effect of contact torques on
porosity of cohesive powders"). Its Fig. 5 is not available as data: only the values its
text and Table 1 give are overlaid on cdpowder's figures."""

# Table 1: (μt, μn) → (σzz, σzz+, σzz−) / p
TABLE1 = {
    (0.0, 0.0): (1.0, 2.2, -1.2),
    (0.1, 0.1): (1.0, 1.4, -0.4),
    (0.3, 0.3): (1.0, 1.1, -0.1),
    (1.0, 1.0): (1.0, 1.1, -0.1),
    (0.0, 0.3): (1.0, 2.2, -1.2),
    (0.0, 1.0): (1.0, 1.9, -0.9),
    (0.3, 0.0): (1.0, 1.2, -0.2),
    (1.0, 0.0): (1.0, 1.4, -0.4),
}
# The porosities and added porosities E1 = E − E0 of its text ("≈" values)
E0 = 0.54
E11 = 0.82
E1_ROLL = 0.18    # E1(1, 0)
E1_TWIST = 0.08   # E1(0, 1)
E1_BOTH = 0.28    # E1(1, 1)
# E1 saturates from about this μ on each line (its text)
SATURATION_MU = 0.4
