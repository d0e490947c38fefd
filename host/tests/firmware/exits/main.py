import sys

print("done early")
sys.exit(3)
