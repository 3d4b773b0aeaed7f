"""The crank mechanism: kinematics, forces, torque and flywheel, and balance."""
