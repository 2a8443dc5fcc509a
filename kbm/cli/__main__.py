import sys

from kbm.cli import main

sys.exit(main())
