"""The wgputrace viewer: `python app.py [SCENE]` (the same as `wgputrace view [SCENE]`)."""

import sys

from wgputrace.app import main

if __name__ == "__main__":
    sys.exit(main())
