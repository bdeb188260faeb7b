// planted: a test folder neither a module tree nor a suite (the tests_layout rule)
