from friction_sweep.cli import main

main()
