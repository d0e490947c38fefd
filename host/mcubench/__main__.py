import sys

from host.rig.targets.mcutime import main

sys.exit(main(sys.argv[1:]))
