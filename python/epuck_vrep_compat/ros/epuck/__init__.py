"""The e-puck topic profiles' faces: sensors and commands, TF, cameras, LEDs and markers."""
