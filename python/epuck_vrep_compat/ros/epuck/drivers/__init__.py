"""What GCtronic's e-puck drivers do beyond the shared topics: the extra topics' face, message
builders and wire layouts, the driver's IR scan and the e-puck2's LED commands."""
