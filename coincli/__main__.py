from coincli.cli import main

main()
