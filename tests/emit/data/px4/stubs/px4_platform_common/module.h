// Test stub: the shape of PX4's ModuleBase, enough to check a generated header's syntax.
#pragma once

template<class T>
class ModuleBase
{
public:
	virtual ~ModuleBase() = default;
};
