from coincli._entry import main

main()
