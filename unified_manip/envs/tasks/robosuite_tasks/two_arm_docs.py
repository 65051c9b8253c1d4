"""The two-arm robosuite tasks' documentation pages."""

TWO_ARM_LIFT_DOC = "TwoArmLift"
TWO_ARM_HANDOVER_DOC = "TwoArmHandover"
