import sys

from host.rig.mcutime import main

sys.exit(main(sys.argv[1:]))
