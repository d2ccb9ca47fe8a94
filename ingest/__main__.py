"""`python -m ingest`: the same service as `gaps serve`, for hosts that run the ingest alone."""
from ingest.serve_args import main

main()
