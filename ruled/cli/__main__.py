import sys

from ruled.cli.main import main

sys.exit(main())
